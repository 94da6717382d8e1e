#include "lib/discrete_error_bound.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "analytic/piece_integrals.h"
#include "lib/reference_integrator.h"

namespace vrv {
namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();
// Nodes of a proxy of an analytic field on one segment (doubled once, then the segment halved).
constexpr int kProxyNodes = 17;
constexpr int kMaxHalvings = 12;

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
Range curve_range(const PiecewiseLinear& curve, double lo, double hi) {
  Range r;
  r.add(std::max(0.0, curve(lo)));
  r.add(std::max(0.0, curve(hi)));
  for (const ControlPoint& p : curve.points())
    if (p.v >= lo && p.v <= hi) r.add(std::max(0.0, p.y));
  return r;
}

// f on one segment: its range (widened by the proxies' error), max |f'| over its pieces and, where
// f is smooth there (no break of the field, every proxy resolved), bounds on |f'| and |f''|.
struct FieldOnSegment {
  Range f;
  double slope = 0;
  bool smooth = true;
  double d1 = 0, d2 = 0;
  long evaluations = 0;
};

// Sum |c_k| of the derivative of a Chebyshev series on [c, d], per unit of t: max |p'| there.
double derivative_bound(std::span<const double> coefficients, double length, std::vector<double>& derivative) {
  derivative.resize(coefficients.size());
  chebyshev_derivative(coefficients, derivative);
  double sum = 0;
  for (double x : derivative) sum += std::abs(x);
  return sum * 2 / length;
}

template <ScalarField F>
void add_piece(const F& field, const Ray& ray, double c, double d, int halvings, FieldOnSegment& out) {
  const int degree = field.degree_along_ray();
  long& evaluations = out.evaluations;
  RayPanel panel = detail::fit_panel(field, ray, c, d, degree >= 0 ? degree + 1 : kProxyNodes, evaluations);
  if (degree < 0 && !panel.resolved) panel = detail::fit_panel(field, ray, c, d, 2 * kProxyNodes - 1, evaluations);
  const double mid = 0.5 * (c + d);
  if (!panel.resolved && halvings < kMaxHalvings && mid > c && mid < d) {
    add_piece(field, ray, c, mid, halvings + 1, out);
    add_piece(field, ray, mid, d, halvings + 1, out);
    return;
  }
  std::vector<Crossing> none;
  const ValueRange exact = find_crossings(panel, {}, none);  // the proxy's exact range
  const double widen = panel.error + panel.noise + 4 * eps * std::max(std::abs(exact.min), std::abs(exact.max));
  out.f.add(Range{exact.min - widen, exact.max + widen});
  std::vector<double> first, second;
  const double slope = derivative_bound(panel.coefficients, d - c, first);
  out.slope = std::max(out.slope, slope);
  if (!panel.resolved) out.smooth = false;
  if (!out.smooth) return;
  out.d1 = std::max(out.d1, slope);
  out.d2 = std::max(out.d2, derivative_bound(first, d - c, second) * 2 / (d - c));
}

template <ScalarField F>
FieldOnSegment field_on(const F& field, const Ray& ray, double a, double b) {
  std::vector<double> cuts{a};
  field.append_breaks(ray, Interval{a, b}, cuts);
  cuts.push_back(b);
  std::sort(cuts.begin(), cuts.end());
  FieldOnSegment out;
  out.smooth = cuts.size() == 2;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i)
    if (cuts[i + 1] > cuts[i]) add_piece(field, ray, cuts[i], cuts[i + 1], 0, out);
  return out;
}

// g(f) and tau(f) on a segment: their ranges and, where smooth, max |d/dt| and |d^2/dt^2|; and
// how far a sample's g and tau can be off the exact ray's because its position is rounded.
struct OpticsOnSegment {
  Range g, tau;
  bool smooth = false;
  double g1 = 0, g2 = 0, tau1 = 0, tau2 = 0;
  double g_rounding = 0, tau_rounding = 0;
};

// position_rounding: how far (in t) a computed sample point can be off the exact ray there.
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

// What the segments add up to (the header's telescoped sum), front to back.
class BoundSum {
 public:
  // A segment of the rule: its emission E and depth dPhi^, and the local bounds eps and delta.
  void add(double emission, double depth, double eps_k, double delta_k) {
    const double reach = std::min(1.0, std::exp(-phi_ + d_));
    bound_ += eps_k * reach + std::abs(emission) * std::exp(-phi_) * std::expm1(d_);
    emission_sum_ += std::abs(emission) * std::exp(-phi_);
    phi_ += depth;
    d_ += delta_k;
    ++segments_;
  }
  double finish(double background) const { return bound_ + background * std::exp(-phi_) * std::expm1(d_) + rounding(background); }
  // Where every segment's emission is kappa (1 - e^-dPhi^) (g = kappa tau, and a rule exact for a
  // constant colour), I_h = kappa + (I0 - kappa) e^-Phi^ as I = kappa + (I0 - kappa) e^-Phi*: only
  // the depth's error remains.
  double finish_proportional(double kappa, double background) const {
    // kappa holds to 8 ulps (TransferFunction::emission_per_extinction), so does each g / tau.
    return std::abs(background - kappa) * std::exp(-phi_) * std::expm1(d_) + rounding(background) + 16 * eps * kappa;
  }
  long segments() const { return segments_; }

 private:
  // The raycaster's product of transparencies against e^-(sum of depths): an ulp or two per factor.
  double rounding(double background) const {
    return 4 * eps * static_cast<double>(segments_ + 1) * (emission_sum_ + background);
  }

  double phi_ = 0, d_ = 0, bound_ = 0, emission_sum_ = 0;
  long segments_ = 0;
};

struct SegmentBounds {
  double emission = 0, depth = 0, eps = 0, delta = 0;
};

// A sample rule's segment [a, b] around its sample m (values g_m, tau_m at m); the part of it in
// the ray's clipped range `inside` alone has light (the true g and tau are 0 outside).
SegmentBounds sample_segment(SegmentRule rule, const OpticsOnSegment& o, double a, double b, double m,
                             double g_m, double tau_m, Interval inside) {
  const double h = b - a;
  const double x = tau_m * h;
  SegmentBounds s;
  s.depth = x;
  // riemann: g dx; alpha: (g / tau) (1 - e^-tau dx), nothing where tau = 0 (colour undefined).
  s.emission = rule == SegmentRule::riemann ? g_m * h : (tau_m > 0 ? g_m / tau_m * (-std::expm1(-x)) : 0.0);
  // The constant reconstruction (g_m, tau_m) integrated exactly over the segment, and over its part
  // inside (from that part's start): their difference is the light of the parts outside.
  const auto constant = [&](double length) {
    const double y = tau_m * length;
    return y > 0 ? g_m * (-std::expm1(-y)) / tau_m : g_m * length;
  };
  const double ia = std::max(a, inside.t0), ib = std::min(b, inside.t1);
  const double hi = std::max(0.0, ib - ia);
  const double whole = constant(h), part = constant(hi);
  const double dev_g = o.g.deviation(g_m), dev_tau = o.tau.deviation(tau_m);
  // Moments of s - m over the inside part.
  const double l = std::clamp(m - ia, 0.0, hi), r = std::clamp(ib - m, 0.0, hi);
  const double mu1 = 0.5 * std::abs(r * r - l * l), mu_abs = 0.5 * (r * r + l * l), mu2 = (r * r * r + l * l * l) / 3;
  const double w = std::max(l, r);
  double delta = hi * dev_tau;
  double rate = dev_tau;  // |int_ia^s (tau - tau_m)| <= rate (s - ia)
  double spread = hi * dev_g;
  if (o.smooth) {
    delta = std::min(delta, o.tau1 * mu1 + 0.5 * o.tau2 * mu2);
    rate = std::min(rate, o.tau1 * w + 0.5 * o.tau2 * w * w);
    // int (g - g_m) e^-int tau: the linear term against the attenuation's departure from 1.
    spread = std::min(spread, o.g1 * (mu1 + o.tau.hi * hi * mu_abs) + 0.5 * o.g2 * mu2);
  }
  const double attenuation = g_m * std::min(hi, rate * 0.5 * hi * hi);
  s.delta = delta + tau_m * (h - hi) + hi * o.tau_rounding;
  s.eps = spread + attenuation + hi * o.g_rounding + std::abs(whole - part) + std::abs(whole - s.emission) +
          16 * eps * (whole + std::abs(s.emission));
  return s;
}

// A segment rule's segment [a, b] between nodes with values (g, tau) at each end.
SegmentBounds node_segment(SegmentRule rule, const OpticsOnSegment& o, double h, double g_a, double g_b,
                           double tau_a, double tau_b) {
  const PieceIntegral linear = linear_piece(h, g_a, g_b, tau_a, tau_b);
  SegmentBounds s;
  s.depth = 0.5 * h * (tau_a + tau_b);
  s.emission = rule == SegmentRule::trapezoid ? trapezoid_segment(h, g_a, g_b, tau_a, tau_b).emission : linear.emission;
  // The linear interpolants stay within the values' ranges; where smooth, within h^2/8 max |u''|.
  double depth_gap = h * o.tau.width(), spread = h * o.g.width();
  if (o.smooth) {
    depth_gap = std::min(depth_gap, h * h * h / 12 * o.tau2);
    spread = std::min(spread, h * h * h / 12 * o.g2);
  }
  s.delta = depth_gap + h * o.tau_rounding;
  const double attenuation = std::max(g_a, g_b) * std::min(h, h * s.delta);
  s.eps = spread + attenuation + h * o.g_rounding + std::abs(linear.emission - s.emission) +
          64 * eps * (std::abs(linear.emission) + std::abs(s.emission));
  return s;
}

}  // namespace

std::string why_no_error_bound(const Scene& scene, const DiscreteConfig& c) {
  if (scene.color) return "an RGB scene (bound one channel at a time)";
  if (!scene.transfer.affine()) return "an opacity/colour transfer function (g and tau not affine in f)";
  switch (c.rule) {
    case SegmentRule::riemann: case SegmentRule::alpha: case SegmentRule::trapezoid: case SegmentRule::exact_linear:
      break;
    default:
      return std::string("rule ") + std::string(segment_rule_name(c.rule)) + " (no bound derived for it)";
  }
  if (c.oversample != 1 || c.correction != Correction::none) return "oversampling or an opacity correction";
  if (c.termination || c.skip_below) return "early termination or skipping";
  if (c.classification != Classification::post) return "pre-classification";
  if (c.precision != Precision::double_precision) return "single precision";
  if (c.table_size != 0) return "transfer-function tables";
  if (c.sampling.strategy == Strategy::partial || c.sampling.strategy == Strategy::exit_anchored)
    return "a strategy with a partial step";
  return {};
}

namespace {

struct Sampled {
  double g = 0, tau = 0;
};

template <ScalarField F>
Sampled sample_at(const F& field, const Ray& ray, const TransferFunction& tf, double t) {
  const double v = field.value(ray.at(t));
  double lo = 0, hi = 0;
  const TransferSegment seg = tf.segment(v, lo, hi);
  return {seg.g(v), seg.tau(v)};
}

template <ScalarField F>
DiscreteErrorBound bound_for(const F& field, const Scene& scene, const Ray& ray, const DiscreteConfig& config) {
  DiscreteErrorBound out;
  const auto iv = clip(ray, scene.box);
  if (!iv) return out;  // the raycast returns the background exactly
  const TransferFunction& tf = scene.transfer;
  const SamplePlan plan = plan_samples(config.sampling, ray, *iv, scene.box);
  BoundSum sum;
  const auto optics = [&](double a, double b) {
    const FieldOnSegment on = field_on(field, ray, std::max(a, iv->t0), std::min(b, iv->t1));
    out.evaluations += on.evaluations;
    // o + t d rounds each coordinate by an ulp or two of |o| + |t| (d is a unit vector).
    const double rounding = 8 * eps * (ray.origin.cwiseAbs().maxCoeff() + std::max(std::abs(a), std::abs(b)));
    return optics_on(tf, on, rounding);
  };
  const auto sample = [&](double t) {
    ++out.evaluations;
    return sample_at(field, ray, tf, t);
  };
  if (!is_segment_rule(config.rule)) {
    const double dx = plan.dt;
    // A stretch of [t0, t1] no sample stands for: E = 0, no depth.
    const auto gap = [&](double a, double b) {
      if (!(b > a)) return;
      const OpticsOnSegment o = optics(a, b);
      sum.add(0, 0, o.g.hi * (b - a), o.tau.hi * (b - a));
      ++out.segments;
    };
    gap(iv->t0, plan.count > 0 ? plan.t(0) - 0.5 * dx : iv->t1);
    for (long k = 0; k < plan.count; ++k) {
      const double m = plan.t(k), a = m - 0.5 * dx, b = m + 0.5 * dx;
      const OpticsOnSegment o = optics(a, b);
      const Sampled s = sample(m);
      const SegmentBounds seg = sample_segment(config.rule, o, a, b, m, s.g, s.tau, *iv);
      sum.add(seg.emission, seg.depth, seg.eps, seg.delta);
      out.smooth += o.smooth;
      ++out.segments;
    }
    if (plan.count > 0) gap(plan.t(plan.count - 1) + 0.5 * dx, iv->t1);
  } else {
    double t_a = iv->t0;
    Sampled a = sample(t_a);
    const auto node = [&](double t_b) {
      const Sampled b = sample(t_b);
      if (t_b > t_a) {
        const OpticsOnSegment o = optics(t_a, t_b);
        const SegmentBounds seg = node_segment(config.rule, o, t_b - t_a, a.g, b.g, a.tau, b.tau);
        sum.add(seg.emission, seg.depth, seg.eps, seg.delta);
        out.smooth += o.smooth;
        ++out.segments;
      }
      t_a = t_b, a = b;
    };
    for (long k = 0; k < plan.count; ++k) node(plan.t(k));
    node(iv->t1);
  }
  out.bound = sum.finish(scene.background);
  // alpha emits (g / tau)(1 - e^-tau dx) and exact_linear integrates linear g = kappa tau exactly.
  const auto kappa = tf.emission_per_extinction();
  if (kappa && (config.rule == SegmentRule::alpha || config.rule == SegmentRule::exact_linear))
    out.bound = std::min(out.bound, sum.finish_proportional(*kappa, scene.background));
  if (!std::isfinite(out.bound)) out.unavailable = "the bound is not finite (a segment's range or derivative overflowed)";
  return out;
}

}  // namespace

DiscreteErrorBound discrete_error_bound(const Scene& scene, const Ray& ray, const DiscreteConfig& config) {
  validate(config, std::holds_alternative<GridField>(scene.field), scene.transfer);
  DiscreteErrorBound out;
  out.unavailable = why_no_error_bound(scene, config);
  if (!out.available()) return out;
  return visit_field(scene, [&](const auto& field) { return bound_for(field, scene, ray, config); });
}

}  // namespace vrv
