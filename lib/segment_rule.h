#pragma once
// How samples become an integral: every rule turns the samples into a sequence of
// (emission E_k, transparency t_k) pairs that a compositor combines,
//   front to back  I = sum_k E_k prod_{j<k} t_j + I0 prod_k t_k,
// so rules and compositing order stay independent.  See docs/discrete-raycasts.md.
#include <cmath>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "analytic/piece_integrals.h"

namespace vrv {

enum class SegmentRule {
  riemann,       // eq. (5) of Steneteg et al.: E = g dx, t = exp(-tau dx), one per sample
  alpha,         // renderer compositing: alpha = 1 - exp(-tau dx), E = c alpha, t = 1 - alpha
  trapezoid,     // between consecutive nodes: trapezoid in tau and in g e^-Phi
  exact_linear,  // g and tau linear between nodes, integrated exactly (pre-integration, no table)
  moreland,      // average-opacity approximation: zeta = 1 - mean alpha, Psi = (1 - zeta)/(D tau_avg)
};

std::optional<SegmentRule> parse_segment_rule(std::string_view name);
std::string segment_rule_list();  // its names in order, "a, b, c": the choices an error offers
std::string_view segment_rule_name(SegmentRule r);
// Every rule, in the order above.
std::span<const SegmentRule> all_segment_rules();
// Sample rules (riemann, alpha) give each sample a step of its own; segment rules integrate
// between consecutive nodes, with the entry and exit points as first and last nodes.
inline bool is_segment_rule(SegmentRule r) {
  return r != SegmentRule::riemann && r != SegmentRule::alpha;
}

template <class Real>
struct Composite {
  Real emission = 0;
  Real transparency = 1;
};

// One sample of the midpoint-type rules.
template <class Real>
Composite<Real> riemann_sample(Real g, Real tau, Real dx) {
  return {g * dx, std::exp(-tau * dx)};
}

// One segment [a, b] of length h between nodes with values (g, tau) at each end.
template <class Real>
Composite<Real> trapezoid_segment(Real h, Real g_a, Real g_b, Real tau_a, Real tau_b) {
  const Real t = std::exp(-Real(0.5) * h * (tau_a + tau_b));
  return {Real(0.5) * h * (g_a + g_b * t), t};
}

template <class Real>
Composite<Real> exact_linear_segment(Real h, Real g_a, Real g_b, Real tau_a, Real tau_b) {
  const PieceIntegral p = linear_piece(h, g_a, g_b, tau_a, tau_b);
  return {static_cast<Real>(p.emission), static_cast<Real>(std::exp(-p.optical_depth))};
}

// Moreland's average-opacity approximation over a segment of length D with colours c (front,
// back) and opacities alpha_f, alpha_b of that segment length: with colour linear in s,
//   I = c_f (1 - Psi) + c_b (Psi - zeta),  zeta = 1 - (alpha_f + alpha_b)/2,  Psi = (1 - zeta)/(D tau).
template <class Real>
Composite<Real> moreland_segment(Real c_f, Real c_b, Real alpha_f, Real alpha_b) {
  const Real mean_alpha = Real(0.5) * (alpha_f + alpha_b);
  const Real zeta = 1 - mean_alpha;
  if (mean_alpha >= 1) return {c_f, 0};  // opaque: everything comes from the front
  const Real depth = -std::log1p(-mean_alpha);  // D tau_avg
  const Real psi = depth == 0 ? Real(1) : mean_alpha / depth;
  return {c_f * (1 - psi) + c_b * (psi - zeta), zeta};
}

}  // namespace vrv
