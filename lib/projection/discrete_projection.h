#pragma once
// Projections as renderers compute them: samples where a placement strategy puts them
// (lib/sampling), each the field as the scene interpolates it (a grid's trilinear or nearest),
// or its extinction (classified modes).
//   MIP:   the largest sample (the first one on a tie), at the plan's samples only.
//   X-ray: riemann    sum of samples x the step each stands for (the partial step's for its length);
//          trapezoid  nodes entry, samples, exit: sum of h (q_a + q_b) / 2;
//          simpson    the same nodes, each segment by Simpson's rule with one more sample at its
//                     midpoint, h (q_a + 4 q_m + q_b) / 6.
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <string_view>

#include "lib/field.h"
#include "lib/projection/projection_mode.h"
#include "lib/sampling.h"
#include "lib/scene.h"

namespace vrv {

enum class XrayRule { riemann, trapezoid, simpson };
std::optional<XrayRule> parse_xray_rule(std::string_view name);  // "riemann", "trapezoid", "simpson"
std::string xray_rule_list();  // its names in order, "a, b, c": the choices an error offers
std::string_view xray_rule_name(XrayRule r);

struct DiscreteProjectionConfig {
  ProjectionMode mode = ProjectionMode::mip;
  SamplingConfig sampling;
  XrayRule rule = XrayRule::trapezoid;  // X-ray modes only
};

struct DiscreteProjectionResult {
  double value = 0;  // 0 for a ray that misses or has no sample
  long samples = 0;  // field samples taken
  double position = std::numeric_limits<double>::quiet_NaN();  // MIP: t of the largest sample
};

namespace projection_detail {

// The plan's sample parameters in ray order (the partial step's sample where the plan puts it),
// each with the length it stands for.
template <class Visit>
void for_each_sample(const SamplePlan& plan, Visit&& visit) {
  if (plan.partial > 0 && plan.partial_first) visit(plan.t_partial, plan.partial);
  for (long k = 0; k < plan.count; ++k) visit(plan.t(k), plan.dt);
  if (plan.partial > 0 && !plan.partial_first) visit(plan.t_partial, plan.partial);
}

}  // namespace projection_detail

template <ScalarField F>
DiscreteProjectionResult discrete_projection(const F& field, const Box& box, const TransferFunction& tf,
                                             const Ray& ray, const DiscreteProjectionConfig& config) {
  DiscreteProjectionResult r;
  const auto iv = clip(ray, box);
  if (!iv) return r;
  const SamplePlan plan = plan_samples(config.sampling, ray, *iv, box);
  const bool classified = is_classified(config.mode);
  const auto q = [&](double t) {
    ++r.samples;
    const double v = field.value(ray.at(t));
    return classified ? classified_value(tf, v) : v;
  };
  if (is_mip(config.mode)) {
    double best = -std::numeric_limits<double>::infinity();
    projection_detail::for_each_sample(plan, [&](double t, double) {
      const double v = q(t);
      if (v > best || std::isnan(v)) best = v, r.position = t;  // a NaN sample is never hidden
    });
    if (r.samples > 0) r.value = best;
    return r;
  }
  double sum = 0;
  if (config.rule == XrayRule::riemann) {
    projection_detail::for_each_sample(plan, [&](double t, double h) { sum += q(t) * h; });
    r.value = sum;
    return r;
  }
  double t_a = iv->t0, q_a = q(t_a);
  const auto node = [&](double t_b) {
    const double h = t_b - t_a;
    if (!(h > 0)) return;
    const double q_b = q(t_b);
    sum += config.rule == XrayRule::trapezoid ? 0.5 * h * (q_a + q_b) : h * (q_a + 4 * q(t_a + 0.5 * h) + q_b) / 6;
    t_a = t_b, q_a = q_b;
  };
  projection_detail::for_each_sample(plan, [&](double t, double) { node(t); });
  node(iv->t1);
  r.value = sum;
  return r;
}

DiscreteProjectionResult discrete_projection(const Scene& scene, const Ray& ray, const DiscreteProjectionConfig& config);

}  // namespace vrv
