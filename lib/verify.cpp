#include "lib/verify.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "lib/verify/channel_errors.h"
#include "lib/verify/conventions.h"
#include "lib/verify/convergence_orders.h"
#include "lib/verify/fault_fit.h"
#include "lib/verify/fault_hints.h"
#include "lib/verify/pixel_geometry.h"
#include "lib/verify/projection_models.h"
#include "lib/work_estimate.h"

namespace vrv {
namespace {

// The reference's tolerance check: its largest estimate and the pixels that miss `tol`; a
// failure naming up to ten of them.
void check_reference(const ReferenceImage& ref, double tol, int width, VerifyReport& rep) {
  ReferenceInfo& info = rep.reference;
  info.tol = tol;
  info.from_cache = ref.from_cache;
  info.cache_file = ref.cache_file;
  for (std::size_t i = 0; i < ref.value.size(); ++i) {
    info.max_error_estimate = std::max(info.max_error_estimate, ref.error_estimate[i]);
    if (!(ref.error_estimate[i] <= tol) || !std::isfinite(ref.value[i])) {
      ++info.missed;
      if (info.missed_pixels.size() < 10)
        info.missed_pixels.emplace_back(static_cast<int>(i % width), static_cast<int>(i / width));
    }
  }
  if (!info.missed) return;
  std::string where;
  for (auto [x, y] : info.missed_pixels) where += fmt::format(" ({}, {})", x, y);
  rep.failures.push_back(fmt::format("the reference misses its tolerance {:g} at {} pixel(s):{}{} (max "
                                     "estimate {:.3g})", tol, info.missed, where,
                                     info.missed > 10 ? " ..." : "", info.max_error_estimate));
}

void count_regions(const PixelGeometry& geo, ReferenceInfo& info) {
  for (std::size_t i = 0; i < geo.hit.size(); ++i) {
    info.hit_pixels += geo.hit[i];
    info.silhouette_pixels += geo.region[i] == Region::silhouette;
    info.jump_pixels += geo.region[i] == Region::tf_jump;
  }
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
  require_grey(scene, "scene", "verify");
  VerifyOptions opt = given;
  if (opt.mode && !opt.expected_order) opt.expected_order = expected_projection_order(*opt.mode, scene.transfer);
  check_inputs(images, opt);
  const std::vector<const ImageWithStep*> sorted = sorted_by_step(images);
  const ChannelImage& first = images.front().image;
  VerifyReport rep;
  rep.width = first.width;
  rep.height = first.height;
  rep.camera = verify_camera(scene, opt, rep.width, rep.height);
  rep.threshold = opt.threshold;
  rep.order_metric = opt.order_metric;
  if (opt.mode) rep.mode = std::string(projection_mode_name(*opt.mode));

  const ReferenceImage ref = reference_image(scene, rep.camera, opt);
  check_reference(ref, opt.reference_tol, rep.width, rep);
  rep.reference_image.assign(ref.value.begin(), ref.value.end());
  const PixelGeometry geo = pixel_geometry(scene, rep.camera, ref, opt);
  count_regions(geo, rep.reference);

  const int nc = static_cast<int>(first.planes.size());
  const double background = opt.mode ? 0.0 : scene.background;  // a projection has none
  for (const ImageWithStep* im : sorted)
    for (int c = 0; c < nc; ++c) rep.channels.push_back(channel_report(*im, c, ref, geo, background, opt));
  judge_orders(rep, sorted, first.names, background, opt);

  const int colour = first_colour_channel(first);
  if (opt.mode) {
    if (opt.diagnose && colour < nc) rep.diagnosis = diagnose_projection(scene, rep.camera, *opt.mode, sorted, colour, opt);
    rep.expected_order = opt.expected_order;
    rep.notes.push_back(kProjectionSkipNote);
    rep.pass = rep.failures.empty();
    return rep;
  }
  if (opt.diagnose && colour < nc) rep.diagnosis = diagnose(scene, rep.camera, sorted, colour, opt);
  rep.faults = find_faults(rep, geo, nc, opt);
  if (colour < nc) decompose_floor(rep, scene, sorted, colour, opt);
  separate_conventions(rep, opt);
  rep.pass = rep.failures.empty();
  return rep;
}

}  // namespace vrv
