#include "lib/verify.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "lib/verify/channel_errors.h"
#include "lib/verify/channel_order.h"
#include "lib/verify/conventions.h"
#include "lib/verify/convergence_orders.h"
#include "lib/verify/fault_fit.h"
#include "lib/verify/fault_hints.h"
#include "lib/verify/pixel_geometry.h"
#include "lib/verify/projection_models.h"
#include "lib/work_estimate.h"

namespace vrv {
namespace {

// The reference's tolerance check over every channel: its largest estimate and the pixels where
// a channel misses `tol`; a failure naming up to ten of them.
void check_reference(const std::vector<ReferenceImage>& refs, double tol, int width, VerifyReport& rep) {
  ReferenceInfo& info = rep.reference;
  info.tol = tol;
  info.from_cache = refs.front().from_cache;
  info.cache_file = refs.front().cache_file;
  for (std::size_t i = 0; i < refs.front().pixel_count(); ++i) {
    bool missed = false;
    for (const ReferenceImage& ref : refs) {
      info.max_error_estimate = std::max(info.max_error_estimate, ref.error_estimate[i]);
      missed = missed || !(ref.error_estimate[i] <= tol) || !std::isfinite(ref.pixels[i]);
    }
    if (!missed) continue;
    ++info.missed;
    if (info.missed_pixels.size() < 10)
      info.missed_pixels.emplace_back(static_cast<int>(i % width), static_cast<int>(i / width));
  }
  if (!info.missed) return;
  std::string where;
  for (auto [x, y] : info.missed_pixels) where += fmt::format(" ({}, {})", x, y);
  rep.failures.push_back(fmt::format("the reference misses its tolerance {:g} at {} pixel(s):{}{} (max "
                                     "estimate {:.3g})", tol, info.missed, where,
                                     info.missed > 10 ? " ..." : "", info.max_error_estimate));
}

// Hit and silhouette pixels are the same in every channel; a jump pixel crosses a jump of any
// channel's transfer function.
void count_regions(const std::vector<PixelGeometry>& geos, ReferenceInfo& info) {
  const PixelGeometry& geo = geos.front();
  for (std::size_t i = 0; i < geo.hit.size(); ++i) {
    info.hit_pixels += geo.hit[i];
    info.silhouette_pixels += geo.region[i] == Region::silhouette;
    info.jump_pixels +=
        std::any_of(geos.begin(), geos.end(), [&](const PixelGeometry& g) { return g.region[i] == Region::tf_jump; });
  }
}

void keep_reference_image(const std::vector<ReferenceImage>& refs, VerifyReport& rep) {
  const std::size_t n = refs.front().pixel_count(), nc = refs.size();
  rep.reference_channels = static_cast<int>(nc);
  rep.reference_image.resize(n * nc);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t c = 0; c < nc; ++c) rep.reference_image[i * nc + c] = static_cast<float>(refs[c].pixels[i]);
}

// The channel the diagnosis reads: the first colour channel (the channel count when there is
// none); for an RGB scene the colour channel with the largest error in the finest image, where a
// fault of one channel (its colour table) shows.
int diagnosed_channel(const VerifyReport& rep, const ChannelImage& first, bool rgb, Metric metric) {
  const int nc = first.channels;
  int colour = first_colour_channel(first);
  if (!rgb) return colour;
  const std::size_t finest = rep.channels.size() - nc;  // image-major, by decreasing step
  for (int c = colour + 1; c < nc; ++c)
    if (c != first.alpha && metric_value(rep.channels[finest + c].all(), metric) >
                                metric_value(rep.channels[finest + colour].all(), metric))
      colour = c;
  return colour;
}

}  // namespace

Camera verify_camera(const Scene& scene, const VerifyOptions& opt, int w, int h) {
  Camera c = opt.camera ? *opt.camera : scene.camera ? *scene.camera : default_camera(scene.box);
  c.width = w, c.height = h;
  try {
    validate(c);
  } catch (const CameraError& e) {
    throw VerifyInputError(fmt::format("camera: {}", e.what()));
  }
  return c;
}

VerificationWork verification_work(const Scene& scene, const VerifyOptions& opt, int w, int h,
                                   const std::vector<double>& steps) {
  const Camera camera = verify_camera(scene, opt, w, h);
  VerificationWork work;
  work.reference = camera_work(scene, camera, opt.reference_tol);
  if (opt.diagnose && !steps.empty())
    work.diagnosis = opt.mode ? projection_diagnosis_work(scene, camera, *opt.mode, steps)
                              : diagnosis_work(scene, camera, steps, opt);
  return work;
}

VerifyReport verify_images(const Scene& scene, const std::vector<ImageWithStep>& images,
                           const VerifyOptions& given) {
  VerifyOptions opt = given;
  if (opt.mode) require_grey(scene, "scene", "verify with a projection mode");
  if (opt.mode) require_unshaded(scene, "scene", "verify with a projection mode");
  if (opt.mode && !opt.expected_order) opt.expected_order = expected_projection_order(*opt.mode, scene.transfer);
  check_inputs(images, opt);
  const std::vector<int> truth = reference_channels(images.front(), scene.channel_count());
  const std::vector<const ImageWithStep*> sorted = sorted_by_step(images);
  const ChannelImage& first = images.front().image;
  VerifyReport rep;
  rep.width = first.width;
  rep.height = first.height;
  rep.camera = verify_camera(scene, opt, rep.width, rep.height);
  rep.threshold = opt.threshold;
  rep.order_metric = opt.order_metric;
  if (opt.mode) rep.mode = std::string(projection_mode_name(*opt.mode));

  const std::vector<ReferenceImage> refs = reference_images(scene, rep.camera, opt);
  check_reference(refs, opt.reference_tol, rep.width, rep);
  keep_reference_image(refs, rep);
  // Scene channel k as a grey scene (the field shared): what each channel's geometry and the
  // diagnosis cast.
  std::vector<Scene> channel_scenes;
  for (int k = 0; k < scene.channel_count(); ++k) channel_scenes.push_back(channel_scene(scene, k));
  std::vector<PixelGeometry> geos;
  for (int k = 0; k < scene.channel_count(); ++k)
    geos.push_back(pixel_geometry(channel_scenes[k], rep.camera, refs[k], opt));
  count_regions(geos, rep.reference);

  const int nc = first.channels;
  std::vector<double> backgrounds;  // a projection has none
  for (int c = 0; c < nc; ++c) backgrounds.push_back(opt.mode ? 0.0 : channel_scenes[truth[c]].background);
  for (const ImageWithStep* im : sorted)
    for (int c = 0; c < nc; ++c)
      rep.channels.push_back(channel_report(*im, c, refs[truth[c]], geos[truth[c]], backgrounds[c], opt));
  judge_orders(rep, sorted, first.names, backgrounds, opt);

  const int colour = diagnosed_channel(rep, first, scene.color.has_value(), opt.order_metric);
  if (opt.mode) {
    if (opt.diagnose && colour < nc) rep.diagnosis = diagnose_projection(scene, rep.camera, *opt.mode, sorted, colour, opt);
    rep.expected_order = opt.expected_order;
    rep.notes.push_back(kProjectionSkipNote);
    rep.pass = rep.failures.empty();
    return rep;
  }
  const int read = colour < nc ? colour : 0;
  const Scene& diagnosed = channel_scenes[truth[read]];
  if (scene.color) rep.diagnosis_channel = first.names[read];
  if (opt.diagnose && colour < nc) rep.diagnosis = diagnose(diagnosed, rep.camera, sorted, colour, opt);
  rep.faults = find_faults(rep, geos[truth[read]], nc, read, opt);
  if (scene.color)
    if (auto swap = swapped_channels(*sorted.back(), truth, refs, *scene.color, opt.alpha)) {
      rep.failures.push_back(fmt::format("swapped channels: {}", swap->evidence));
      rep.faults.push_back(std::move(*swap));
    }
  if (colour < nc) decompose_floor(rep, diagnosed, sorted, colour, opt);
  separate_conventions(rep, opt);
  rep.pass = rep.failures.empty();
  return rep;
}

}  // namespace vrv
