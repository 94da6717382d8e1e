#include "lib/verify/reference_image.h"

#include <iostream>

#include <fmt/format.h>

#include "lib/reference_pixels.h"
#include "lib/util/progress.h"
#include "lib/verify/projection_models.h"
#include "lib/verify/reference_cache.h"

namespace vrv {
namespace {

namespace fs = std::filesystem;

ReferenceImage render_reference(const Scene& scene, const Camera& camera, double tol, bool progress) {
  ReferenceImage r;
  r.width = camera.width, r.height = camera.height;
  const long n = pixel_count(camera);
  r.value.resize(n), r.error_estimate.resize(n), r.optical_depth.resize(n);
  Progress bar("reference", n, progress);
  ImageLoopHooks hooks;
  hooks.progress = [&](long done) { bar.advance(done); };
  reference_pixels(scene, camera, {tol}, [&](long i, const ReferenceResult& v) {
    r.value[i] = v.value, r.error_estimate[i] = v.error_estimate, r.optical_depth[i] = v.optical_depth;
  }, hooks);
  bar.finish();
  return r;
}

// An optional cache that cannot be written (a full disk) does not fail the computed run.
void try_to_cache(const fs::path& dir, const fs::path& file, const std::string& key, ReferenceImage& r) {
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
  const bool cache = !opt.cache_dir.empty() && !opt.scene_text.empty();
  std::string key;
  fs::path file;
  if (cache) {
    // A volume's files change behind the same scene text: their digest joins the key (empty,
    // and the key as before, for every other scene).
    // A projection's mode joins it too (nothing joins it for emission-absorption).
    const std::string mode = opt.mode ? projection_cache_tag(*opt.mode) : std::string();
    key = reference_cache_key(opt.scene_text + scene.field_files + mode, camera, opt.reference_tol);
    file = opt.cache_dir / reference_cache_name(key);
    if (auto r = read_reference_cache(file, key, camera.width, camera.height)) return *r;
  }
  ReferenceImage r = opt.mode ? projection_reference_image(scene, camera, *opt.mode, opt.reference_tol, opt.progress)
                              : render_reference(scene, camera, opt.reference_tol, opt.progress);
  if (cache) try_to_cache(opt.cache_dir, file, key, r);
  return r;
}

}  // namespace vrv
