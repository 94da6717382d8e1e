#pragma once
// The field and the optics g(f), tau(f) on one short stretch [a, b] of a ray (a discrete rule's
// segment), from Chebyshev proxies fitted there: ranges, derivative bounds, values and derivatives
// at a point.  What the a-priori bound (lib/discrete_error_bound.h) and the error estimate
// (lib/discrete_error_estimate.h) know about a segment.
#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include "lib/field.h"
#include "lib/reference_integrator.h"
#include "lib/transfer_function.h"

namespace vrv {

struct Range {
  double lo = INFINITY, hi = -INFINITY;
  void add(double x) { lo = std::min(lo, x), hi = std::max(hi, x); }
  void add(Range r) { lo = std::min(lo, r.lo), hi = std::max(hi, r.hi); }
  double width() const { return hi - lo; }
  // max |x - y| over x in the range.
  double deviation(double y) const { return std::max(hi - y, y - lo); }
};

// A curve's values over [lo, hi]: its values at the ends and at the control points between (both
// sides of a jump), clamped at 0 as TransferSegment clamps.
Range curve_range(const PiecewiseLinear& curve, double lo, double hi);

// f, df/dt and d2f/dt2 at one point.
struct FieldDerivatives {
  double f = 0, d1 = 0, d2 = 0;
};

// f on one segment: its proxies (one per piece between the field's breaks, halved where 17 nodes
// do not resolve f), its range (widened by the proxies' error), max |f'| over them and, where f is
// smooth there (no break of the field, every proxy resolved), bounds on |f'| and |f''|.
struct FieldOnSegment {
  std::vector<RayPanel> panels;  // in ray order, tiling the segment
  Range f;
  double slope = 0;
  bool smooth = true;
  double d1 = 0, d2 = 0;
  long evaluations = 0;

  // From the proxy whose piece holds t.
  FieldDerivatives at(double t) const;
};

// Nodes of a proxy of an analytic field on one segment (doubled once, then the segment halved).
inline constexpr int kSegmentProxyNodes = 17;

namespace detail {

// Adds the proxy (or proxies) of [c, d], a piece without a break of the field, to `out`.
void add_segment_panel(RayPanel panel, FieldOnSegment& out);

template <ScalarField F>
void add_segment_piece(const F& field, const Ray& ray, double c, double d, int halvings, FieldOnSegment& out) {
  constexpr int kMaxHalvings = 12;
  const int degree = field.degree_along_ray();
  RayPanel panel = fit_panel(field, ray, c, d, degree >= 0 ? degree + 1 : kSegmentProxyNodes, out.evaluations);
  if (degree < 0 && !panel.resolved) panel = fit_panel(field, ray, c, d, 2 * kSegmentProxyNodes - 1, out.evaluations);
  const double mid = 0.5 * (c + d);
  if (!panel.resolved && halvings < kMaxHalvings && mid > c && mid < d) {
    add_segment_piece(field, ray, c, mid, halvings + 1, out);
    add_segment_piece(field, ray, mid, d, halvings + 1, out);
    return;
  }
  add_segment_panel(std::move(panel), out);
}

}  // namespace detail

template <ScalarField F>
FieldOnSegment field_on(const F& field, const Ray& ray, double a, double b) {
  std::vector<double> cuts{a};
  field.append_breaks(ray, Interval{a, b}, cuts);
  cuts.push_back(b);
  std::sort(cuts.begin(), cuts.end());
  FieldOnSegment out;
  out.smooth = cuts.size() == 2;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i)
    if (cuts[i + 1] > cuts[i]) detail::add_segment_piece(field, ray, cuts[i], cuts[i + 1], 0, out);
  return out;
}

// g(f) and tau(f) on a segment: their ranges and, where smooth (f smooth, no transfer-function
// breakpoint in its range), max |d/dt| and |d^2/dt^2|; and how far a sample's g and tau can be off
// the exact ray's because its position is rounded.
struct OpticsOnSegment {
  Range g, tau;
  bool smooth = false;
  double g1 = 0, g2 = 0, tau1 = 0, tau2 = 0;
  double g_rounding = 0, tau_rounding = 0;
};

// position_rounding: how far (in t) a computed sample point can be off the exact ray there.
OpticsOnSegment optics_on(const TransferFunction& tf, const FieldOnSegment& on, double position_rounding);

// The ray's light I from above, segment by segment front to back: each stretch's largest g over
// its length, attenuated by the smallest depth of the stretches before it.  I >= 0 and I_h >= 0,
// so I_h - I lies in [I_h - upper, I_h]: the bound's cap and the estimate's clamp.
class LightFromAbove {
 public:
  // A stretch of `length` inside the box where g <= g_hi and tau >= tau_lo.
  void add(double g_hi, double tau_lo, double length) {
    light_ += g_hi * length * std::exp(-depth_);
    depth_ += tau_lo * length;
  }
  double upper(double background) const { return light_ + background * std::exp(-depth_); }

 private:
  double light_ = 0, depth_ = 0;
};

}  // namespace vrv
