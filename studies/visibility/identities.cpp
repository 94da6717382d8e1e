// The opacity identities of Gao et al. (IEEE Vis 2003) and the radiance bound behind early
// termination and culling; see identities.h.
#include "studies/visibility/identities.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace vrv {

double scaled_opacity(double alpha, double k) { return -std::expm1(k * std::log1p(-alpha)); }

double combined_opacity(std::span<const double> alphas, std::span<const double> ks) {
  if (alphas.size() != ks.size()) throw std::invalid_argument("combined_opacity: sizes differ");
  double log_transparency = 0;  // sum k_i log(1 - alpha_i): the product in log space
  for (std::size_t i = 0; i < alphas.size(); ++i) log_transparency += ks[i] * std::log1p(-alphas[i]);
  return -std::expm1(log_transparency);
}

double combined_opacity_of_depths(std::span<const double> depths, std::span<const double> ks) {
  if (depths.size() != ks.size()) throw std::invalid_argument("combined_opacity_of_depths: sizes differ");
  double depth = 0;
  for (std::size_t i = 0; i < depths.size(); ++i) depth += ks[i] * depths[i];
  return -std::expm1(-depth);
}

double samples_to_threshold(double alpha, double threshold) {
  return std::log1p(-threshold) / std::log1p(-alpha);
}

namespace {

// g / tau at v on one affine branch; the limit slope ratio where both vanish.
double colour_at(const TransferSegment& s, double v) {
  const double g = s.g(v), tau = s.tau(v);
  if (tau > 0) return g / tau;
  if (g > 0) return std::numeric_limits<double>::infinity();
  return s.second.slope != 0 ? std::max(0.0, s.first.slope / s.second.slope) : 0.0;
}

}  // namespace

double max_colour(const TransferFunction& tf) {
  if (tf.convention() == Convention::opacity_color) return std::max(0.0, tf.second().max_value());
  const std::vector<double>& b = tf.breakpoints();
  if (b.empty()) return colour_at(tf.segment(0.0), 0.0);
  double m = 0;
  // Below the first and above the last control value both curves are constant.
  constexpr double inf = std::numeric_limits<double>::infinity();
  const double below = value_inside(-inf, b.front()), above = value_inside(b.back(), inf);
  m = std::max(m, colour_at(tf.segment(below), below));
  m = std::max(m, colour_at(tf.segment(above), above));
  for (std::size_t i = 0; i + 1 < b.size(); ++i) {
    const TransferSegment s = tf.segment(value_inside(b[i], b[i + 1]));
    m = std::max({m, colour_at(s, b[i]), colour_at(s, b[i + 1])});
  }
  return m;
}

double max_radiance(const TransferFunction& tf, double background) {
  return std::max(max_colour(tf), background);
}

PiecewiseLinear scaled(const PiecewiseLinear& curve, double k) {
  std::vector<ControlPoint> p = curve.points();
  for (ControlPoint& c : p) c.y *= k;
  return PiecewiseLinear(std::move(p));
}

PiecewiseLinear sum(const PiecewiseLinear& a, const PiecewiseLinear& b) {
  // The left limit at v: the first of two equal control values, else the value itself.
  auto left = [](const PiecewiseLinear& c, double v) {
    const auto& p = c.points();
    for (std::size_t i = 0; i + 1 < p.size(); ++i)
      if (p[i].v == v && p[i + 1].v == v) return p[i].y;
    return c(v);
  };
  std::vector<double> vs;
  for (const auto* c : {&a, &b})
    for (const ControlPoint& p : c->points()) vs.push_back(p.v);
  std::sort(vs.begin(), vs.end());
  vs.erase(std::unique(vs.begin(), vs.end()), vs.end());
  std::vector<ControlPoint> out;
  for (double v : vs) {
    const double l = left(a, v) + left(b, v), r = a(v) + b(v);
    if (l != r) out.push_back({v, l});
    out.push_back({v, r});
  }
  return PiecewiseLinear(std::move(out));
}

TransferFunction absorption_only(const PiecewiseLinear& extinction, double k) {
  return TransferFunction::emission_extinction(PiecewiseLinear({{0.0, 0.0}}), scaled(extinction, k));
}

}  // namespace vrv
