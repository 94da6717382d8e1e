// The sampling study's computations; see fan.h.
#include "studies/sampling/fan.h"

#include <cmath>
#include <algorithm>
#include <numbers>

#include "lib/util/parallel.h"
#include "lib/reference_integrator.h"
#include "studies/engine/reference_audit.h"

namespace vrv::sampling_study {
namespace {

constexpr double kDegree = std::numbers::pi / 180;

}  // namespace

std::array<double, 2> to_square_frame(const FanSetup& s, std::array<double, 2> p) {
  // Rotating the square by +alpha about its centre is the same as keeping it axis-aligned and
  // rotating everything else by -alpha about that centre.
  const double a = -s.rotation_degrees * kDegree;
  const double dx = p[0] - s.centre[0], dy = p[1] - s.centre[1];
  return {s.centre[0] + std::cos(a) * dx - std::sin(a) * dy,
          s.centre[1] + std::sin(a) * dx + std::cos(a) * dy};
}

Camera fan_camera(const FanSetup& s) {
  const auto eye = to_square_frame(s, s.eye);
  Camera c;
  c.projection = Projection::fan;
  c.eye = Vec3(eye[0], eye[1], 0);
  c.fov_degrees = s.fov_degrees;
  c.angle_degrees = s.angle_degrees - s.rotation_degrees;
  c.width = s.rays;
  c.height = 1;
  validate(c);
  return c;
}

Camera image_camera(const FanSetup& s, int width, int height) {
  const auto eye = to_square_frame(s, s.eye);
  const double a = (s.angle_degrees - s.rotation_degrees) * kDegree;
  Camera c;
  c.projection = Projection::perspective;
  c.eye = Vec3(eye[0], eye[1], 0);
  c.target = c.eye + Vec3(std::cos(a), std::sin(a), 0);
  // right = forward x up: with up = -z, right turns counter-clockwise, as the fan's index does.
  c.up = Vec3(0, 0, -1);
  c.fov_degrees = s.fov_degrees;
  c.width = width;
  c.height = height;
  validate(c);
  return c;
}

DiscreteConfig strategy_config(const Scene& scene, SegmentRule rule, Strategy strategy, double rate,
                               const Vec3& eye) {
  DiscreteConfig c;
  c.rule = rule;
  c.sampling.strategy = strategy;
  c.sampling.rate = rate;
  c.sampling.dims = scene.dims;
  c.sampling.eye = eye;
  return c;
}

double fan_angle_degrees(const FanSetup& s, int i) {
  return s.angle_degrees - s.fov_degrees / 2 + s.fov_degrees * (i + 0.5) / s.rays;
}

std::vector<ContinuousRay> continuous_rays(const Scene& scene, const std::vector<Ray>& rays, double tol,
                                           ReferenceAudit& audit) {
  std::vector<ContinuousRay> out(rays.size());
  parallel_for_index(static_cast<long>(rays.size()), [&](long i) {
    const Ray& ray = rays[static_cast<std::size_t>(i)];
    ContinuousRay& r = out[static_cast<std::size_t>(i)];
    if (const auto iv = clip(ray, scene.box)) r.chord = iv->length();
    const ReferenceResult ref = audited_reference(audit, scene, ray, ReferenceOptions{tol});
    r.value = ref.value;
    r.estimate = ref.error_estimate;
  });
  return out;
}

std::vector<RayValue> discrete_rays(const Scene& scene, const std::vector<Ray>& rays,
                                    const DiscreteConfig& c) {
  std::vector<RayValue> out(rays.size());
  visit_field(scene, [&](const auto& field) {
    const auto caster = scene_raycaster(field, scene, c);
    parallel_for_index(static_cast<long>(rays.size()), [&](long i) {
      const DiscreteResult r = caster.cast(rays[static_cast<std::size_t>(i)]);
      out[static_cast<std::size_t>(i)] = {r.value, r.samples};
    });
  });
  return out;
}

FanStats ray_error_stats(const std::vector<ContinuousRay>& truth, const std::vector<RayValue>& rays) {
  FanStats st;
  ErrorSums sums;
  double samples = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    if (!std::isfinite(rays[i].value)) ++st.nonfinite;
    if (!(truth[i].chord > 0)) continue;
    sums.add(std::abs(rays[i].value - truth[i].value));
    if (rays[i].samples == 0) ++st.dropped;
    samples += static_cast<double>(rays[i].samples);
  }
  st.error = sums.stats();
  if (st.error.count > 0) st.mean_samples = samples / static_cast<double>(st.error.count);
  return st;
}

Image to_image(const Camera& camera, const std::vector<double>& values) {
  Image img(camera.width, camera.height);
  for (std::size_t p = 0; p < values.size() && p < img.pixels.size(); ++p)
    img.pixels[p] = static_cast<float>(values[p]);
  return img;
}

}  // namespace vrv::sampling_study
