#include "lib/discrete_error_bound.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "analytic/piece_integrals.h"
#include "lib/rule_segments.h"
#include "lib/segment_field.h"

namespace vrv {
namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();
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
  // The ray's light from a stretch of `length` inside the box where g <= g_hi and tau >= tau_lo.
  void add_light(double g_hi, double tau_lo, double length) { light_.add(g_hi, tau_lo, length); }
  double finish(double background) const {
    return std::min(bound_ + background * std::exp(-phi_) * std::expm1(d_) + rounding(background), either(background));
  }
  // Where every segment's emission is kappa (1 - e^-dPhi^) (g = kappa tau, and a rule exact for a
  // constant colour), I_h = kappa + (I0 - kappa) e^-Phi^ as I = kappa + (I0 - kappa) e^-Phi*: only
  // the depth's error remains.
  double finish_proportional(double kappa, double background) const {
    // kappa holds to 8 ulps (TransferFunction::emission_per_extinction), so does each g / tau.
    return std::min(std::abs(background - kappa) * std::exp(-phi_) * std::expm1(d_) + rounding(background) + 16 * eps * kappa,
                    either(background));
  }
  long segments() const { return segments_; }

 private:
  // The raycaster's product of transparencies against e^-(sum of depths): an ulp or two per factor.
  double rounding(double background) const {
    return 4 * eps * static_cast<double>(segments_ + 1) * (emission_sum_ + background);
  }

  // I and I_h are both >= 0, so |I - I_h| <= max(I, I_h): I from above through the segments' ranges
  // of g and tau, I_h as composited.  Where the depth errors compound (e^D_k, optically thick
  // segments the steps do not resolve) this is the smaller.
  double either(double background) const {
    const double upper = light_.upper(background);
    const double discrete = emission_sum_ + background * std::exp(-phi_);
    return (1 + 16 * eps * static_cast<double>(segments_ + 1)) * std::max(upper, discrete);
  }

  double phi_ = 0, d_ = 0, bound_ = 0, emission_sum_ = 0;
  LightFromAbove light_;
  long segments_ = 0;
};

struct SegmentBounds {
  double emission = 0, depth = 0, eps = 0, delta = 0;
};

// A sample rule's segment [a, b] around its sample m; the part of it in the ray's clipped range
// `inside` alone has light (the true g and tau are 0 outside).
SegmentBounds sample_segment(const RuleSegment& seg, const OpticsOnSegment& o, Interval inside) {
  const double a = seg.a, b = seg.b, m = seg.m, g_m = seg.g_m, tau_m = seg.tau_m;
  const double h = b - a;
  SegmentBounds s;
  s.depth = seg.depth;
  s.emission = seg.emission;
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
  // The ends m -+ dx/2 are rounded, so consecutive segments overlap or leave gaps of an ulp or two
  // of |t| (the exact integral is over a partition): light and depth of that much ray, per segment.
  // On far rays with a thousand segments this is the bound's largest rounding term.
  const double tiling = 4 * eps * (std::abs(a) + std::abs(b));
  s.delta = delta + tau_m * (h - hi) + hi * o.tau_rounding + tiling * o.tau.hi;
  s.eps = spread + attenuation + hi * o.g_rounding + std::abs(whole - part) + std::abs(whole - s.emission) +
          16 * eps * (whole + std::abs(s.emission)) + tiling * o.g.hi;
  return s;
}

// A segment rule's segment [a, b] between nodes with values (g, tau) at each end.
SegmentBounds node_segment(const RuleSegment& seg, const OpticsOnSegment& o) {
  const double h = seg.b - seg.a;
  const PieceIntegral linear = linear_piece(h, seg.g_a, seg.g_b, seg.tau_a, seg.tau_b);
  SegmentBounds s;
  s.depth = seg.depth;
  s.emission = seg.emission;
  // The linear interpolants stay within the values' ranges; where smooth, within h^2/8 max |u''|.
  double depth_gap = h * o.tau.width(), spread = h * o.g.width();
  if (o.smooth) {
    depth_gap = std::min(depth_gap, h * h * h / 12 * o.tau2);
    spread = std::min(spread, h * h * h / 12 * o.g2);
  }
  s.delta = depth_gap + h * o.tau_rounding;
  const double attenuation = std::max(seg.g_a, seg.g_b) * std::min(h, h * s.delta);
  s.eps = spread + attenuation + h * o.g_rounding + std::abs(linear.emission - s.emission) +
          64 * eps * (std::abs(linear.emission) + std::abs(s.emission));
  return s;
}

}  // namespace

std::string outside_segment_analysis(const DiscreteConfig& c) {
  if (c.rule == SegmentRule::moreland) return "rule moreland";
  if (c.oversample != 1 || c.correction != Correction::none) return "oversampling or an opacity correction";
  if (c.termination || c.skip_below) return "early termination or skipping";
  if (c.classification != Classification::post) return "pre-classification";
  if (c.precision != Precision::double_precision) return "single precision";
  if (c.table_size != 0) return "transfer-function tables";
  return {};
}

DiscreteConfig analysed_configuration(const DiscreteConfig& c) {
  if (outside_segment_analysis(c).empty()) return c;
  DiscreteConfig base;
  // Moreland composites the nodes exact_linear integrates (its own approximation is the difference).
  base.rule = c.rule == SegmentRule::moreland ? SegmentRule::exact_linear : c.rule;
  base.sampling = c.sampling;
  // N samples per step: one per step N times shorter (the oversamples' offset from these, where
  // there is one, is in the difference too).
  (step_based(c.sampling.strategy) ? base.sampling.step : base.sampling.rate) =
      step_based(c.sampling.strategy) ? c.sampling.step / c.oversample : c.sampling.rate * c.oversample;
  base.compositing = c.compositing;
  return base;
}

std::string why_no_error_bound(const Scene& scene, const DiscreteConfig& c) {
  if (scene.color) return "an RGB scene (bound one channel at a time)";
  if (!scene.transfer.affine()) return "an opacity/colour transfer function (g and tau not affine in f)";
  if (c.sampling.strategy == Strategy::partial || c.sampling.strategy == Strategy::exit_anchored)
    return "a strategy with a partial step";
  return {};
}

double cast_difference(const Scene& scene, const Ray& ray, const DiscreteConfig& config, const DiscreteConfig& base,
                       long& evaluations) {
  const DiscreteResult own = discrete_raycast(scene, ray, config), analysed = discrete_raycast(scene, ray, base);
  evaluations += own.samples + analysed.samples;
  return own.value - analysed.value;
}

namespace {

template <ScalarField F>
DiscreteErrorBound bound_for(const F& field, const Scene& scene, const Ray& ray, const DiscreteConfig& config) {
  DiscreteErrorBound out;
  const auto iv = clip(ray, scene.box);
  if (!iv) return out;  // the raycast returns the background exactly
  const TransferFunction& tf = scene.transfer;
  BoundSum sum;
  const long samples = for_each_rule_segment(field, ray, tf, config, *iv, scene.box, [&](const RuleSegment& seg) {
    const double ia = std::max(seg.a, iv->t0), ib = std::min(seg.b, iv->t1);
    const FieldOnSegment on = field_on(field, ray, ia, ib);
    out.evaluations += on.evaluations;
    // o + t d rounds each coordinate by an ulp or two of |o| + |t| (d is a unit vector).
    const double rounding = 8 * eps * (ray.origin.cwiseAbs().maxCoeff() + std::max(std::abs(seg.a), std::abs(seg.b)));
    const OpticsOnSegment o = optics_on(tf, on, rounding);
    ++out.segments;
    sum.add_light(o.g.hi, std::max(0.0, o.tau.lo), std::max(0.0, ib - ia));
    if (seg.gap) {  // E = 0, no depth: everything there is missed
      sum.add(0, 0, o.g.hi * (seg.b - seg.a), o.tau.hi * (seg.b - seg.a));
      return;
    }
    const SegmentBounds b = is_segment_rule(config.rule) ? node_segment(seg, o) : sample_segment(seg, o, *iv);
    sum.add(b.emission, b.depth, b.eps, b.delta);
    out.smooth += o.smooth;
  });
  out.evaluations += samples;
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
  const DiscreteConfig base = analysed_configuration(config);
  out = visit_field(scene, [&](const auto& field) { return bound_for(field, scene, ray, base); });
  if (outside_segment_analysis(config).empty() || !out.available()) return out;
  // |I_h - I| <= |I_h - I_h(base)| + |I_h(base) - I|, the difference rounded once.
  out.cast_difference = cast_difference(scene, ray, config, base, out.evaluations);
  out.bound += std::abs(out.cast_difference) * (1 + 2 * eps);
  return out;
}

}  // namespace vrv
