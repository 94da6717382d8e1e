#include "lib/verify/reference_image.h"

#include <algorithm>
#include <array>
#include <iostream>
#include <optional>

#include <fmt/format.h>

#include "lib/reference_pixels.h"
#include "lib/util/progress.h"
#include "lib/util/ranks.h"
#include "lib/verify/projection_models.h"
#include "lib/verify/reference_cache.h"

namespace vrv {
namespace {

namespace fs = std::filesystem;

ReferenceImage render_reference(const Scene& scene, const Camera& camera, double tol, bool progress) {
  ReferenceImage r(camera.width, camera.height);
  Progress bar("reference", pixel_count(camera), progress);
  ImageLoopHooks hooks;
  hooks.progress = [&](long done) { bar.advance(done); };
  reference_pixels(scene, camera, {tol}, [&](long i, const ReferenceResult& v) {
    r.pixels[i] = v.value, r.error_estimate[i] = v.error_estimate, r.optical_depth[i] = v.optical_depth;
  }, hooks);
  bar.finish();
  return r;
}

// What verify keeps of an RGB pixel's reference (the record MPI ranks exchange): each channel's
// value and estimate, and the deepest channel's optical depth.  Each channel's depth is a lower
// bound where that channel stopped early (its remaining emission negligible): the largest of the
// three is the alpha channel's truth.
struct ColorPixel {
  std::array<double, 3> value, estimate;
  double optical_depth;
};
ColorPixel color_pixel(const ChannelsReferenceResult& v) {
  ColorPixel p{};
  for (int c = 0; c < 3; ++c) {
    p.value[c] = v.channel[c].value, p.estimate[c] = v.channel[c].error_estimate;
    p.optical_depth = std::max(p.optical_depth, v.channel[c].optical_depth);
  }
  return p;
}

// The three channels of an RGB scene from one walk per ray.
std::vector<ReferenceImage> render_color_reference(const Scene& scene, const Camera& camera, double tol,
                                                   bool progress) {
  std::vector<ReferenceImage> r(3, ReferenceImage(camera.width, camera.height));
  Progress bar("reference", pixel_count(camera), progress);
  ImageLoopHooks hooks;
  hooks.progress = [&](long done) { bar.advance(done); };
  const ImageChannels channels(scene, false);
  image_channel_pixels(scene, camera, channels, {tol}, color_pixel, [&](long i, const ColorPixel& p) {
    for (int c = 0; c < 3; ++c)
      r[c].pixels[i] = p.value[c], r[c].error_estimate[i] = p.estimate[c], r[c].optical_depth[i] = p.optical_depth;
  }, hooks);
  bar.finish();
  return r;
}

// Where the cache keeps a reference: the key (the scene's text, its volume files' digest, the
// projection's mode or the RGB channel: whatever makes the image differ) and its file; nothing
// when the cache is off.
struct CacheSlot {
  fs::path file;
  std::string key;
};
std::optional<CacheSlot> cache_slot(const Scene& scene, const Camera& camera, const VerifyOptions& opt,
                                    const std::string& tag) {
  if (opt.cache_dir.empty() || opt.scene_text.empty()) return std::nullopt;
  CacheSlot slot;
  slot.key = reference_cache_key(opt.scene_text + scene.field_files + tag, camera, opt.reference_tol);
  slot.file = opt.cache_dir / reference_cache_name(slot.key);
  return slot;
}

// An optional cache that cannot be written (a full disk) does not fail the computed run.
void try_to_cache(const fs::path& dir, const fs::path& file, const std::string& key, ReferenceImage& r) {
  if (!is_output_rank()) return;  // under MPI, rank 0 writes
  std::error_code ec;
  fs::create_directories(dir, ec);
  try {
    write_reference_cache(file, key, r);
    r.cache_file = file.string();
  } catch (const std::runtime_error& e) {
    std::cerr << fmt::format("vrv: the reference cache was not written: {}\n", e.what());
  }
}

}  // namespace

ReferenceImage reference_image(const Scene& scene, const Camera& camera, const VerifyOptions& opt) {
  require_grey(scene, "scene", "reference_image");
  // Nothing joins the key for emission-absorption: grey entries keep the keys they always had.
  const auto slot = cache_slot(scene, camera, opt, opt.mode ? projection_cache_tag(*opt.mode) : std::string());
  std::optional<ReferenceImage> cached;
  if (slot) cached = read_reference_cache(slot->file, slot->key, camera.width, camera.height);
  if (on_every_rank(cached.has_value())) return *cached;
  ReferenceImage r = opt.mode ? projection_reference_image(scene, camera, *opt.mode, opt.reference_tol, opt.progress)
                              : render_reference(scene, camera, opt.reference_tol, opt.progress);
  if (slot) try_to_cache(opt.cache_dir, slot->file, slot->key, r);
  return r;
}

std::vector<ReferenceImage> reference_images(const Scene& scene, const Camera& camera, const VerifyOptions& opt) {
  if (!scene.color) return {reference_image(scene, camera, opt)};
  if (opt.mode) require_grey(scene, "scene", "a projection's reference image");
  std::vector<std::optional<CacheSlot>> slots;
  std::vector<ReferenceImage> cached;
  for (int c = 0; c < 3; ++c) {
    slots.push_back(cache_slot(scene, camera, opt, fmt::format("#rgb channel {}", c)));
    if (slots.back())
      if (auto r = read_reference_cache(slots.back()->file, slots.back()->key, camera.width, camera.height))
        cached.push_back(std::move(*r));
  }
  if (on_every_rank(cached.size() == 3)) return cached;
  std::vector<ReferenceImage> r = render_color_reference(scene, camera, opt.reference_tol, opt.progress);
  for (int c = 0; c < 3; ++c)
    if (slots[c]) try_to_cache(opt.cache_dir, slots[c]->file, slots[c]->key, r[c]);
  return r;
}

}  // namespace vrv
