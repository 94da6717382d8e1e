#include "lib/transfer_function.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

namespace vrv {

PiecewiseLinear::PiecewiseLinear(std::vector<ControlPoint> points) : points_(std::move(points)) {
  if (points_.empty()) throw std::invalid_argument("needs at least one control point");
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const auto& p = points_[i];
    if (!std::isfinite(p.v) || !std::isfinite(p.y))
      throw std::invalid_argument(fmt::format("control point {} is not finite", i));
    if (i > 0 && p.v < points_[i - 1].v)
      throw std::invalid_argument(fmt::format("control values are not sorted at point {}", i));
    if (i > 1 && p.v == points_[i - 2].v)
      throw std::invalid_argument(
          fmt::format("value {} is repeated more than twice (a jump takes exactly two)", p.v));
    // A piece's line is its ends' slope: a span or slope that overflows would make it 0 or NaN.
    if (i > 0 && p.v > points_[i - 1].v) {
      const double dv = p.v - points_[i - 1].v;
      if (!std::isfinite(dv))
        throw std::invalid_argument(fmt::format("values {} and {} at points {} and {} are too far apart (their "
                                                "difference overflows)", points_[i - 1].v, p.v, i - 1, i));
      if (!std::isfinite((p.y - points_[i - 1].y) / dv))
        throw std::invalid_argument(fmt::format("the slope between points {} and {} overflows (values {} and {} "
                                                "too close for the change {} to {})", i - 1, i, points_[i - 1].v,
                                                p.v, points_[i - 1].y, p.y));
    }
  }
}

double value_inside(double lo, double hi) {
  if (std::isinf(lo)) return std::isinf(hi) ? 0.0 : hi - std::max(1.0, std::abs(hi));  // below hi, whatever its size
  if (std::isinf(hi)) return lo;
  const double mid = 0.5 * lo + 0.5 * hi;  // no overflow
  return lo < mid && mid < hi ? mid : lo;
}

namespace {

// The first control point past v_inside: the piece holding it ends there.
std::vector<ControlPoint>::const_iterator first_after(const std::vector<ControlPoint>& points, double v_inside) {
  return std::upper_bound(points.begin(), points.end(), v_inside,
                          [](double v, const ControlPoint& p) { return v < p.v; });
}

}  // namespace

Line PiecewiseLinear::line_at(double v_inside) const {
  const auto after = first_after(points_, v_inside);
  if (after == points_.begin()) return Line{points_.front().v, points_.front().y, 0};
  if (after == points_.end()) return Line{points_.back().v, points_.back().y, 0};
  const ControlPoint& a = *(after - 1);
  const ControlPoint& b = *after;
  // Anchored at the end of smaller |y|: y0 + slope (v - v0) then adds terms of one sign for a
  // non-negative line, a few ulps of the result.  Anchored at the other end it cancels: from
  // (-1e6, 1e6) down to (0, 0), v = -0.1 gave 1e6 - (1e6 - 0.1), off by ulps of 1e6.
  const ControlPoint& anchor = std::abs(b.y) < std::abs(a.y) ? b : a;
  return Line{anchor.v, anchor.y, (b.y - a.y) / (b.v - a.v)};
}

double PiecewiseLinear::on_piece(double v_inside, double v) const {
  const auto after = first_after(points_, v_inside);
  if (after != points_.begin() && after != points_.end()) {
    if (v == (after - 1)->v) return (after - 1)->y;
    if (v == after->v) return after->y;
  }
  return line_at(v_inside)(v);  // a tail's line is its one value, exactly
}

double PiecewiseLinear::operator()(double v) const { return line_at(v)(v); }

double PiecewiseLinear::max_value() const {
  return std::max_element(points_.begin(), points_.end(),
                          [](auto& a, auto& b) { return a.y < b.y; })->y;
}

double PiecewiseLinear::min_value() const {
  return std::min_element(points_.begin(), points_.end(),
                          [](auto& a, auto& b) { return a.y < b.y; })->y;
}

bool PiecewiseLinear::zero_on(double lo, double hi) const {
  if (!((*this)(lo) == 0 && (*this)(hi) == 0)) return false;
  return std::all_of(points_.begin(), points_.end(),
                     [&](const ControlPoint& p) { return p.v < lo || p.v > hi || p.y == 0; });
}

void PiecewiseLinear::append_zero_candidates(double lo, double hi, std::vector<double>& out) const {
  out.push_back(lo), out.push_back(hi);
  for (const ControlPoint& p : points_)
    if (p.v >= lo && p.v <= hi) out.push_back(p.v);
}

double PiecewiseLinear::max_abs_slope() const {
  double s = 0;
  for (std::size_t i = 1; i < points_.size(); ++i) {
    const double dv = points_[i].v - points_[i - 1].v;
    if (dv > 0) s = std::max(s, std::abs(points_[i].y - points_[i - 1].y) / dv);
  }
  return s;
}

TransferFunction TransferFunction::emission_extinction(PiecewiseLinear emission,
                                                       PiecewiseLinear extinction) {
  if (emission.min_value() < 0) throw std::invalid_argument("emission must not be negative");
  if (extinction.min_value() < 0) throw std::invalid_argument("extinction must not be negative");
  TransferFunction tf;
  tf.convention_ = Convention::emission_extinction;
  tf.first_ = std::move(emission);
  tf.second_ = std::move(extinction);
  tf.finish();
  return tf;
}

TransferFunction TransferFunction::without_emission() const {
  // No emission between the whole function's first and last breakpoints (cuts it has already):
  // a table over its breakpoints' range then covers the same values as this function's.
  const double lo = breakpoints_.front(), hi = breakpoints_.back();
  const PiecewiseLinear none = lo < hi ? PiecewiseLinear({{lo, 0.0}, {hi, 0.0}}) : PiecewiseLinear({{lo, 0.0}});
  return affine() ? emission_extinction(none, second_) : opacity_color(first_, none, unit_length_);
}

TransferFunction TransferFunction::opacity_color(PiecewiseLinear opacity, PiecewiseLinear color,
                                                 double unit_length) {
  if (!(unit_length > 0) || !std::isfinite(unit_length))
    throw std::invalid_argument("unit_length must be a positive finite number");
  if (opacity.min_value() < 0) throw std::invalid_argument("opacity must not be negative");
  if (opacity.max_value() >= 1)
    throw std::invalid_argument("opacity must be below 1 (opacity 1 is infinite extinction)");
  if (color.min_value() < 0) throw std::invalid_argument("color must not be negative");
  TransferFunction tf;
  tf.convention_ = Convention::opacity_color;
  tf.first_ = std::move(opacity);
  tf.second_ = std::move(color);
  tf.unit_length_ = unit_length;
  tf.finish();
  return tf;
}

TransferSegment TransferFunction::segment(double v_inside) const {
  return TransferSegment{convention_, first_.line_at(v_inside), second_.line_at(v_inside),
                         unit_length_};
}

bool TransferFunction::transparent_on(double lo, double hi) const {
  // Opacity 0 is tau 0, and g = color x tau.
  if (convention_ == Convention::opacity_color) return first_.zero_on(lo, hi);
  return first_.zero_on(lo, hi) && second_.zero_on(lo, hi);
}

bool TransferFunction::transparent_somewhere(double lo, double hi) const {
  // Each curve is linear between its control points, so the set where both are zero, within
  // [lo, hi], is a union of intervals (open or closed) ending at lo, hi or a control point: it
  // holds one of those ends or the midpoint of two consecutive ones.
  std::vector<double> ends;
  first_.append_zero_candidates(lo, hi, ends);
  if (convention_ != Convention::opacity_color) second_.append_zero_candidates(lo, hi, ends);
  std::sort(ends.begin(), ends.end());
  ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
  for (std::size_t i = 0; i < ends.size(); ++i) {
    if (transparent_on(ends[i], ends[i])) return true;
    const double mid = i + 1 < ends.size() ? 0.5 * ends[i] + 0.5 * ends[i + 1] : ends[i];  // no overflow
    if (transparent_on(mid, mid)) return true;
  }
  return false;
}

TransferFunction::Slopes TransferFunction::slope_bounds(double v_lo, double v_hi) const {
  const auto& b = breakpoints_;
  const auto first = std::lower_bound(b.begin(), b.end(), v_lo) - b.begin();
  const auto last = std::upper_bound(b.begin(), b.end(), v_hi) - b.begin();
  Slopes out;
  for (auto s = first; s <= last; ++s) {
    out.emission = std::max(out.emission, segment_slopes_[s].emission);
    out.extinction = std::max(out.extinction, segment_slopes_[s].extinction);
  }
  return out;
}

TransferFunction::Jump TransferFunction::signed_jump_at(double v) const {
  const auto it = std::lower_bound(breakpoints_.begin(), breakpoints_.end(), v);
  if (it == breakpoints_.end() || *it != v) return {};
  return jumps_[it - breakpoints_.begin()];
}

TransferFunction::Slopes TransferFunction::jump_at(double v) const {
  const Jump j = signed_jump_at(v);
  return {std::abs(j.emission), std::abs(j.extinction)};
}

TransferSegment TransferFunction::segment(double v, double& lo, double& hi) const {
  const auto& b = breakpoints_;
  const auto k = std::upper_bound(b.begin(), b.end(), v) - b.begin();
  lo = k == 0 ? -std::numeric_limits<double>::infinity() : b[k - 1];
  hi = k == static_cast<long>(b.size()) ? std::numeric_limits<double>::infinity() : b[k];
  return segment(v);
}

double TransferFunction::emission(double v) const { return segment(v).g(v); }
double TransferFunction::extinction(double v) const { return segment(v).tau(v); }

void TransferFunction::finish() {
  breakpoints_.clear();
  for (const auto* curve : {&first_, &second_})
    for (const auto& p : curve->points()) breakpoints_.push_back(p.v);
  std::sort(breakpoints_.begin(), breakpoints_.end());
  breakpoints_.erase(std::unique(breakpoints_.begin(), breakpoints_.end()), breakpoints_.end());

  // Every segment's branch at both of its ends, plus the constant tails: g and tau are
  // monotone (or products of monotone factors) on a branch, so the ends bound them.
  struct Sample { double g, tau; };
  std::vector<Sample> samples;
  // g and tau on the branch holding v_inside at one of its ends v, from the curves' control
  // values where v is one: a maximum, or the two sides of a kink, are then exact.
  // (A segment of flat lines through those values: the conventions' formulas stay in
  // TransferSegment.)
  const auto at_end = [&](double v_inside, double v) {
    const TransferSegment ends{convention_, Line{v, first_.on_piece(v_inside, v), 0},
                               Line{v, second_.on_piece(v_inside, v), 0}, unit_length_};
    return Sample{ends.g(v), ends.tau(v)};
  };
  segment_slopes_.clear();
  const double inf = std::numeric_limits<double>::infinity();
  max_ratio_ = 0;
  auto add_branch = [&](double v_inside, double lo, double hi) {
    const TransferSegment s = segment(v_inside);
    Slopes slopes;
    for (double v : {lo, hi}) {
      const Sample end = at_end(v_inside, v);
      const double tau = end.tau;
      if (convention_ == Convention::emission_extinction) {
        slopes.extinction = std::abs(s.second.slope);
        slopes.emission = std::abs(s.first.slope);
      } else {
        const double a = std::max(0.0, first_.on_piece(v_inside, v));
        const double dtau = std::abs(s.first.slope) / (unit_length_ * (1 - a));
        slopes.extinction = std::max(slopes.extinction, dtau);
        slopes.emission = std::max(slopes.emission, std::abs(s.second.slope) * tau +
                                                        std::max(0.0, second_.on_piece(v_inside, v)) * dtau);
      }
      samples.push_back(end);
      // g / tau is monotone on a branch (a ratio of affine functions, or the colour), so its
      // ends bound it; where both vanish its limit is the ratio of the slopes.
      const double g = end.g;
      const double dg = convention_ == Convention::emission_extinction ? std::abs(s.first.slope) : 0.0;
      const double dtau = convention_ == Convention::emission_extinction ? std::abs(s.second.slope) : 0.0;
      const double ratio = tau > 0 ? g / tau : g > 0 ? inf : dg == 0 ? 0.0 : dtau > 0 ? dg / dtau : inf;
      max_ratio_ = std::max(max_ratio_, ratio);
    }
    segment_slopes_.push_back(slopes);
  };
  const auto& b = breakpoints_;
  // The stretch below b[i] and the one above it: [lo(i), b[i]) and [b[i], lo(i + 1)).
  const auto lo = [&](std::size_t i) { return i == 0 ? -inf : b[i - 1]; };
  const auto hi = [&](std::size_t i) { return i == b.size() ? inf : b[i]; };
  add_branch(value_inside(-inf, b.front()), b.front(), b.front());
  for (std::size_t i = 1; i < b.size(); ++i) add_branch(value_inside(b[i - 1], b[i]), b[i - 1], b[i]);
  add_branch(value_inside(b.back(), inf), b.back(), b.back());

  jumps_.clear();
  for (std::size_t i = 0; i < b.size(); ++i) {
    const double below = value_inside(lo(i), hi(i));
    const double above = value_inside(hi(i), hi(i + 1));
    // Exact values on both sides: a kink's sides are one control value, so its jump is 0.
    const Sample l = at_end(below, b[i]), r = at_end(above, b[i]);
    jumps_.push_back({r.g - l.g, r.tau - l.tau});
  }

  max_g_ = max_dg_ = max_dtau_ = 0;
  double max_tau = 0, g_at_max_tau = 0;
  for (const auto& s : samples) {
    max_g_ = std::max(max_g_, s.g);
    if (s.tau > max_tau) max_tau = s.tau, g_at_max_tau = s.g;
  }
  max_tau_ = max_tau;
  for (const auto& s : segment_slopes_) {
    max_dg_ = std::max(max_dg_, s.emission);
    max_dtau_ = std::max(max_dtau_, s.extinction);
  }
  if (convention_ == Convention::opacity_color) {
    // g <= max color * max tau on every branch.
    max_g_ = second_.max_value() * -std::log1p(-first_.max_value()) / unit_length_;
    max_ratio_ = std::max(0.0, second_.max_value());  // g / tau is the colour
  }

  kappa_.reset();
  if (convention_ == Convention::opacity_color) {
    // g = color * tau: proportional exactly when the color is one constant.
    if (second_.min_value() == second_.max_value()) kappa_ = second_.max_value();
    return;
  }
  // Emission and extinction are linear on each segment, so agreement at its ends is enough.
  const double kappa = max_tau > 0 ? g_at_max_tau / max_tau : 0.0;
  const double eps = std::numeric_limits<double>::epsilon();
  const bool proportional = std::all_of(samples.begin(), samples.end(), [&](const Sample& s) {
    return std::abs(s.g - kappa * s.tau) <= 8 * eps * (s.g + kappa * s.tau);
  });
  if (proportional) kappa_ = kappa;
}

}  // namespace vrv
