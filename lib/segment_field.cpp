#include "lib/segment_field.h"

namespace vrv {
namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();

// Sum |c_k| of the derivative of a Chebyshev series on a piece of this length, per unit of t:
// max |p'| there.
double derivative_bound(std::span<const double> coefficients, double length, std::vector<double>& derivative) {
  derivative.resize(coefficients.size());
  chebyshev_derivative(coefficients, derivative);
  double sum = 0;
  for (double x : derivative) sum += std::abs(x);
  return sum * 2 / length;
}

}  // namespace

Range curve_range(const PiecewiseLinear& curve, double lo, double hi) {
  Range r;
  r.add(std::max(0.0, curve(lo)));
  r.add(std::max(0.0, curve(hi)));
  for (const ControlPoint& p : curve.points())
    if (p.v >= lo && p.v <= hi) r.add(std::max(0.0, p.y));
  return r;
}

FieldDerivatives FieldOnSegment::at(double t) const {
  const auto holds = std::find_if(panels.begin(), panels.end(), [&](const RayPanel& p) { return t <= p.b; });
  const RayPanel& p = holds == panels.end() ? panels.back() : *holds;
  const double x = std::clamp(p.x_of(t), -1.0, 1.0), scale = 2 / (p.b - p.a);
  std::vector<double> first(p.coefficients.size()), second(p.coefficients.size());
  chebyshev_derivative(p.coefficients, first);
  chebyshev_derivative(first, second);
  return {chebyshev_evaluate(p.coefficients, x), chebyshev_evaluate(first, x) * scale,
          chebyshev_evaluate(second, x) * scale * scale};
}

namespace detail {

void add_segment_panel(RayPanel panel, FieldOnSegment& out) {
  std::vector<Crossing> none;
  const ValueRange exact = find_crossings(panel, {}, none);  // the proxy's exact range
  const double widen = panel.error + panel.noise + 4 * eps * std::max(std::abs(exact.min), std::abs(exact.max));
  out.f.add(Range{exact.min - widen, exact.max + widen});
  std::vector<double> first, second;
  const double length = panel.b - panel.a;
  const double slope = derivative_bound(panel.coefficients, length, first);
  out.slope = std::max(out.slope, slope);
  if (!panel.resolved) out.smooth = false;
  if (out.smooth) {
    out.d1 = std::max(out.d1, slope);
    out.d2 = std::max(out.d2, derivative_bound(first, length, second) * 2 / length);
  }
  out.panels.push_back(std::move(panel));
}

}  // namespace detail

OpticsOnSegment optics_on(const TransferFunction& tf, const FieldOnSegment& on, double position_rounding) {
  OpticsOnSegment o;
  const double df = on.slope * position_rounding;
  o.g_rounding = tf.max_emission_slope() * df;
  o.tau_rounding = tf.max_extinction_slope() * df;
  o.g = curve_range(tf.first(), on.f.lo, on.f.hi);
  o.tau = curve_range(tf.second(), on.f.lo, on.f.hi);
  const auto& bp = tf.breakpoints();
  const auto first = std::lower_bound(bp.begin(), bp.end(), on.f.lo);
  o.smooth = on.smooth && (first == bp.end() || *first > on.f.hi);
  if (o.smooth) {
    const TransferSegment seg = tf.segment(0.5 * (on.f.lo + on.f.hi));
    const double sg = std::abs(seg.first.slope), st = std::abs(seg.second.slope);
    o.g1 = sg * on.d1, o.g2 = sg * on.d2, o.tau1 = st * on.d1, o.tau2 = st * on.d2;
  }
  return o;
}

}  // namespace vrv
