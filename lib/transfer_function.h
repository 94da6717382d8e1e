#pragma once
// Transfer functions: emission g(v) and extinction tau(v) of the scalar value v.
//
// Both are given as piecewise-linear control points, constant beyond the ends; a repeated
// value makes a jump.  Between two consecutive control values (of either curve) g and tau
// are smooth, so the integrators split rays where the field crosses those values.
#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "lib/util/force_inline.h"

namespace vrv {

struct ControlPoint {
  double v = 0;  // scalar value
  double y = 0;  // function value
};

// y0 + slope * (v - v0): one linear piece, extended beyond its own interval on purpose, so
// that a value a rounding error outside a segment does not fall onto the next branch.  (v0, y0)
// is the piece's end of smaller |y| (PiecewiseLinear::line_at), so the sum does not cancel.
struct Line {
  double v0 = 0;
  double y0 = 0;
  double slope = 0;
  double operator()(double v) const { return y0 + slope * (v - v0); }
};

class PiecewiseLinear {
 public:
  PiecewiseLinear() = default;
  // Requires at least one point, finite numbers, non-decreasing v and no value repeated
  // more than twice; throws std::invalid_argument naming the reason otherwise.
  explicit PiecewiseLinear(std::vector<ControlPoint> points);

  double operator()(double v) const;  // right-continuous at jumps
  // The linear piece that holds v_inside (a value strictly between two breakpoints).
  Line line_at(double v_inside) const;
  // The piece holding v_inside, at v: its control value where v is one of the piece's ends
  // (exact: the line rounds at its end away from its anchor), else the line's value.
  double on_piece(double v_inside, double v) const;
  const std::vector<ControlPoint>& points() const { return points_; }
  double max_value() const;
  double min_value() const;
  double max_abs_slope() const;
  // Zero at every value in [lo, hi] (jumps included).
  bool zero_on(double lo, double hi) const;
  // lo, hi and the control points between them (appended to out): where the function may start
  // or stop being zero in [lo, hi].
  void append_zero_candidates(double lo, double hi, std::vector<double>& out) const;

 private:
  std::vector<ControlPoint> points_;
};

enum class Convention {
  emission_extinction,  // g = emission(v), tau = extinction(v), per unit world length
  opacity_color,        // renderer's: tau = -ln(1 - opacity(v)) / unit_length, g = color(v) * tau
};

// g and tau on one smooth branch (between two consecutive breakpoints).
struct TransferSegment {
  Convention convention = Convention::emission_extinction;
  Line first;   // emission or opacity
  Line second;  // extinction or color
  double unit_length = 1;

  // Clamped at 0 so that a rounding excursion past a zero-crossing never gives negative values.
  // Inline: the discrete raycaster classifies every sample through them.
  VRV_FORCE_INLINE double tau(double v) const {
    if (convention == Convention::emission_extinction) return std::max(0.0, second(v));
    const double a = std::max(0.0, first(v));
    return -std::log1p(-a) / unit_length;
  }
  VRV_FORCE_INLINE double g(double v) const {
    if (convention == Convention::emission_extinction) return std::max(0.0, first(v));
    return std::max(0.0, second(v)) * tau(v);
  }
  // g at v given t = tau(v): the opacity convention's -log1p(-a) computed once for both.
  VRV_FORCE_INLINE double g_given_tau(double v, double t) const {
    if (convention == Convention::emission_extinction) return std::max(0.0, first(v));
    return std::max(0.0, second(v)) * t;
  }
  // The line tau is made of (the extinction, or the opacity with unit_length).
  const Line& extinction_line() const { return convention == Convention::emission_extinction ? second : first; }
};

// A value on the stretch [lo, hi) between consecutive breakpoints (lo < hi; lo = -inf for the
// stretch below the first, hi = +inf above the last), so that segment() of it is that stretch's
// branch: the midpoint where it rounds strictly inside, else lo itself (segment() gives a
// breakpoint the branch above it).  hi - 1 and the midpoint of neighbouring doubles are not
// inside past 2^53 (a jump at 2^54 took the branch above it for the one below).
double value_inside(double lo, double hi);

class TransferFunction {
 public:
  TransferFunction() = default;
  static TransferFunction emission_extinction(PiecewiseLinear emission, PiecewiseLinear extinction);
  // opacity values must lie in [0, 1); unit_length > 0.
  static TransferFunction opacity_color(PiecewiseLinear opacity, PiecewiseLinear color,
                                        double unit_length);

  // The same extinction (opacity and unit length) without emission, over the same range of
  // breakpoints: its reference over a background of 1 is the transmittance e^-Phi, the alpha
  // channel's complement.
  TransferFunction without_emission() const;

  Convention convention() const { return convention_; }
  const PiecewiseLinear& first() const { return first_; }
  const PiecewiseLinear& second() const { return second_; }
  double unit_length() const { return unit_length_; }

  // Sorted distinct control values of both curves.
  const std::vector<double>& breakpoints() const { return breakpoints_; }
  // The branch valid around v_inside; use a value strictly inside a segment.
  TransferSegment segment(double v_inside) const;
  // The branch right-continuous at v, and the range [lo, hi) of values it holds for.
  TransferSegment segment(double v, double& lo, double& hi) const;
  double emission(double v) const;    // right-continuous
  double extinction(double v) const;  // right-continuous

  // g and tau affine in v on every segment (the emission/extinction convention).
  bool affine() const { return convention_ == Convention::emission_extinction; }
  // kappa when g = kappa * tau for every v; then I = kappa (1 - e^-Phi) needs only Phi.
  std::optional<double> emission_per_extinction() const { return kappa_; }

  // Bounds used to turn a field error into an error on I.
  struct Slopes {
    double emission = 0;    // max |dg/dv|
    double extinction = 0;  // max |dtau/dv|
  };
  // Over the values in [v_lo, v_hi] (both sides of any breakpoint in it).
  Slopes slope_bounds(double v_lo, double v_hi) const;
  // g = tau = 0 at every value in [lo, hi]: a stretch whose values stay there adds nothing.
  bool transparent_on(double lo, double hi) const;
  // g = tau = 0 at some value in [lo, hi]: false means no stretch of values in it is transparent,
  // so a field whose values stay there has no empty space to look for.
  bool transparent_somewhere(double lo, double hi) const;
  // |g(v+) - g(v-)| and |tau(v+) - tau(v-)|: nonzero only at the jumps of a step function.
  Slopes jump_at(double v) const;
  // g(v+) - g(v-) and tau(v+) - tau(v-), signed (zero but at a jump).
  struct Jump {
    double emission = 0;
    double extinction = 0;
  };
  Jump signed_jump_at(double v) const;
  double max_emission() const { return max_g_; }
  double max_extinction() const { return max_tau_; }  // max tau over all values
  // sup g / tau where tau > 0, infinite when g > 0 somewhere tau = 0: the emission of any stretch
  // is at most this times its absorbed fraction 1 - e^-Phi, so at most this, however long.
  double max_emission_per_extinction() const { return max_ratio_; }
  double max_emission_slope() const { return max_dg_; }
  double max_extinction_slope() const { return max_dtau_; }

 private:
  void finish();  // breakpoints, kappa and bounds

  Convention convention_ = Convention::emission_extinction;
  PiecewiseLinear first_;
  PiecewiseLinear second_;
  double unit_length_ = 1;
  std::vector<double> breakpoints_;
  std::optional<double> kappa_;
  std::vector<Slopes> segment_slopes_;  // below b_0, between b_{i-1} and b_i, above the last
  std::vector<Jump> jumps_;           // at each breakpoint
  double max_g_ = 0;
  double max_tau_ = 0;
  double max_ratio_ = 0;
  double max_dg_ = 0;
  double max_dtau_ = 0;
};

}  // namespace vrv
