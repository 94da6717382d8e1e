#pragma once
// The segments a plain discrete raycast composites along one ray, each with the emission E_k and
// depth dPhi^_k the raycaster gives it: what the a-priori bound and the error estimate analyse
// segment by segment (docs/error-bounds.md).
//
// Sample rules (riemann, alpha): the sample m stands for [m - dx/2, m + dx/2], which may reach
// past the clipped range [t0, t1]; the ends of [t0, t1] that no sample stands for are `gap`
// segments (E = 0, no depth).  Segment rules (trapezoid, exact_linear): between consecutive nodes,
// the entry and the exit included.  One sample per step, no correction, termination or tables
// (why_no_error_bound, lib/discrete_error_bound.h, says which configurations these are).
#include <cmath>

#include "analytic/piece_integrals.h"
#include "lib/discrete_raycast.h"

namespace vrv {

struct RuleSegment {
  double a = 0, b = 0;
  bool gap = false;
  double m = 0, g_m = 0, tau_m = 0;                  // sample rules: the sample and its g, tau
  double g_a = 0, g_b = 0, tau_a = 0, tau_b = 0;     // segment rules: the nodes' g, tau
  double emission = 0, depth = 0;                    // E_k, dPhi^_k as the raycaster composites them
};

namespace detail {

struct Optical {
  double g = 0, tau = 0;
};

template <ScalarField F>
Optical sample_optics(const F& field, const Ray& ray, const TransferFunction& tf, double t) {
  const double v = field.value(ray.at(t));
  double lo = 0, hi = 0;
  const TransferSegment seg = tf.segment(v, lo, hi);
  return {seg.g(v), seg.tau(v)};
}

}  // namespace detail

// Calls visit(const RuleSegment&) front to back; returns the samples taken (the raycaster's).
template <ScalarField F, class Visit>
long for_each_rule_segment(const F& field, const Ray& ray, const TransferFunction& tf, const DiscreteConfig& config,
                           Interval iv, const Box& box, Visit&& visit) {
  const SamplePlan plan = plan_samples(config.sampling, ray, iv, box);
  long samples = 0;
  const auto sample = [&](double t) {
    ++samples;
    return detail::sample_optics(field, ray, tf, t);
  };
  if (!is_segment_rule(config.rule)) {
    const double dx = plan.dt;
    const auto gap = [&](double a, double b) {
      if (b > a) visit(RuleSegment{a, b, true});
    };
    gap(iv.t0, plan.count > 0 ? plan.t(0) - 0.5 * dx : iv.t1);
    for (long k = 0; k < plan.count; ++k) {
      RuleSegment s;
      s.m = plan.t(k), s.a = s.m - 0.5 * dx, s.b = s.m + 0.5 * dx;
      const detail::Optical o = sample(s.m);
      s.g_m = o.g, s.tau_m = o.tau;
      const double x = o.tau * dx;
      s.depth = x;
      // riemann: g dx; alpha: (g / tau)(1 - e^-tau dx), nothing where tau = 0 (colour undefined).
      s.emission = config.rule == SegmentRule::riemann ? o.g * dx : (o.tau > 0 ? o.g / o.tau * (-std::expm1(-x)) : 0.0);
      visit(s);
    }
    if (plan.count > 0) gap(plan.t(plan.count - 1) + 0.5 * dx, iv.t1);
    return samples;
  }
  double t_a = iv.t0;
  detail::Optical a = sample(t_a);
  const auto node = [&](double t_b) {
    const detail::Optical b = sample(t_b);
    if (t_b > t_a) {
      RuleSegment s;
      s.a = t_a, s.b = t_b, s.m = 0.5 * (t_a + t_b);
      s.g_a = a.g, s.g_b = b.g, s.tau_a = a.tau, s.tau_b = b.tau;
      const double h = t_b - t_a;
      s.depth = 0.5 * h * (a.tau + b.tau);
      s.emission = config.rule == SegmentRule::trapezoid ? trapezoid_segment(h, a.g, b.g, a.tau, b.tau).emission
                                                         : linear_piece(h, a.g, b.g, a.tau, b.tau).emission;
      visit(s);
    }
    t_a = t_b, a = b;
  };
  for (long k = 0; k < plan.count; ++k) node(plan.t(k));
  node(iv.t1);
  return samples;
}

}  // namespace vrv
