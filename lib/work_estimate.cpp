#include "lib/work_estimate.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "lib/discrete_raycast_impl.h"
#include "lib/reference_integrator.h"
#include "lib/sampling.h"

namespace vrv {

Ray box_diagonal(const Box& box) {
  const Vec3 d = box.extent();
  const double n = d.norm();
  return {box.min, n > 0 ? Vec3(d / n) : Vec3(1, 0, 0)};
}

// The raycast's own count (DiscreteRaycaster::cast_in) without casting: the oversampled plan's
// samples and its partial step's, the entry and exit nodes of a segment rule, and the unit samples Lee & Newman's
// correction looks up when the oversamples are centred.
double discrete_samples(const DiscreteConfig& config, const Scene& scene, const Ray& ray) {
  const auto iv = clip(ray, scene.box);
  if (!iv) return 0;
  const SamplePlan plan = plan_samples(config.sampling, ray, *iv, scene.box);
  const SamplePlan fine = detail::oversampled(plan, config.oversample, config.centred_oversamples);
  double samples = static_cast<double>(fine.count) + (plan.partial > 0 ? 1 : 0);
  if (is_segment_rule(config.rule)) samples += 2;
  if (detail::looks_up_unit_samples(config)) samples += static_cast<double>(plan.count);
  return samples;
}

double discrete_samples(const DiscreteConfig& config, const Scene& scene) {
  return discrete_samples(config, scene, box_diagonal(scene.box));
}

double reference_evaluations(const Scene& scene, const Ray& ray, double tol) {
  const auto iv = clip(ray, scene.box);
  if (!iv) return 0;
  // The same stretches and first panels as integrate_reference (lib/reference_integrator.h).
  return visit_field(scene, [&](const auto& field) {
    std::vector<double> cuts{iv->t0};
    field.append_breaks(ray, *iv, cuts);
    cuts.push_back(iv->t1);
    std::sort(cuts.begin(), cuts.end());
    const int degree = field.degree_along_ray();
    double evaluations = 0;
    for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
      const double a = cuts[i], b = cuts[i + 1];
      if (!(b > a)) continue;  // as integrate_reference: an empty stretch costs nothing
      evaluations += degree >= 0 ? degree + 1
                                 : detail::kPanelNodes * first_panel_count(first_panel_length(field.bandwidth(), tol, a, b), a, b);
    }
    return std::min(evaluations, static_cast<double>(detail::kMaxEvaluations));
  });
}

double reference_evaluations(const Scene& scene, double tol) {
  return reference_evaluations(scene, box_diagonal(scene.box), tol);
}

double grid_reference_evaluations(const std::array<int, 3>& nodes, int degree) {
  const double cells = std::max(1, nodes[0] - 1) + std::max(1, nodes[1] - 1) + std::max(1, nodes[2] - 1);
  return cells * (degree + 1);
}

double evaluations_per_sample(const DiscreteConfig& config, const Scene& scene) {
  if (!scene.shading) return 1;
  switch (config.gradient) {
    case GradientScheme::central: return 7;   // six differences
    case GradientScheme::analytic: return 2;  // about one evaluation's worth
    default: return 4;                        // three interpolated gradient grids
  }
}

double camera_work(const Scene& scene, const Camera& camera, double tol, const DiscreteConfig* config) {
  constexpr int kSide = 64;  // at most kSide x kSide pixels are estimated
  const double per_sample = config ? evaluations_per_sample(*config, scene) : 1;
  const int sx = std::min(camera.width, kSide), sy = std::min(camera.height, kSide);
  double work = 0;
  for (int j = 0; j < sy; ++j)
    for (int i = 0; i < sx; ++i) {
      // The centre of each sub-grid cell, a pixel of the image.
      const Ray ray = camera.ray(static_cast<int>((i + 0.5) * camera.width / sx),
                                 static_cast<int>((j + 0.5) * camera.height / sy));
      work += config ? per_sample * discrete_samples(*config, scene, ray) : reference_evaluations(scene, ray, tol);
    }
  return work * (static_cast<double>(camera.width) * camera.height) / (static_cast<double>(sx) * sy);
}

std::string work_limit_allowing(double work) {
  if (!(work > 0) || !std::isfinite(work)) return fmt::format("{:.2g}", work);
  const double unit = std::pow(10.0, std::floor(std::log10(work)) - 1);
  return fmt::format("{:.2g}", std::ceil(work / unit) * unit);
}

}  // namespace vrv
