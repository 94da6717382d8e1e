#include "lib/discrete_error_estimate.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <boost/math/quadrature/gauss.hpp>

#include "analytic/piece_integrals.h"
#include "lib/discrete_error_bound.h"
#include "lib/rule_segments.h"
#include "lib/segment_field.h"

namespace vrv {
namespace {

using Gauss = boost::math::quadrature::gauss<double, 15>;

// M_n = int_{-h/2}^{h/2} x^n w dx, n = 0..3, with the rule's own attenuation across the segment
// w = e^-(tau y + slope y^2 / 2), y = x + h/2 (slope: a linear reconstruction's dtau/dt); beyond 60
// optical depths w is below e^-60 and left out (a boundary layer Gauss-Legendre would not see).
struct Moments {
  double m[4] = {0, 0, 0, 0};
};
Moments moments(double tau, double slope, double h) {
  const double end = tau > 0 ? std::min(h, 60 / tau) : h;
  Moments out;
  for (int n = 0; n < 4; ++n)
    out.m[n] = Gauss::integrate(
        [&](double y) { return std::pow(y - 0.5 * h, n) * std::exp(-(tau * y + 0.5 * slope * y * y)); }, 0.0, end);
  return out;
}

// The exact emission (attenuated from the piece's start) and depth of the proxied field over the
// pieces of `on`, cut where f crosses a transfer-function breakpoint.
struct Local {
  double emission = 0, depth = 0;
};
Local exact_on(const FieldOnSegment& on, const TransferFunction& tf) {
  Local out;
  const auto& levels = tf.breakpoints();
  for (const RayPanel& panel : on.panels) {
    std::vector<Crossing> crossings;
    if (may_cross(panel, levels)) find_crossings(panel, levels, crossings);
    std::vector<double> cuts{panel.a};
    for (const Crossing& x : crossings) cuts.push_back(x.t);
    cuts.push_back(panel.b);
    for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
      const double c = cuts[i], d = cuts[i + 1];
      if (!(d > c)) continue;
      const TransferSegment seg = tf.segment(panel(0.5 * (c + d)));
      const auto tau = [&](double s) { return seg.tau(panel(s)); };
      const double phi = out.depth;
      out.emission += Gauss::integrate(
          [&](double s) { return seg.g(panel(s)) * std::exp(-(phi + (s > c ? Gauss::integrate(tau, c, s) : 0.0))); }, c, d);
      out.depth += Gauss::integrate(tau, c, d);
    }
  }
  return out;
}

// The constant reconstruction (g, tau) integrated exactly over a length h from its start.
double constant_emission(double g, double tau, double h) {
  const double x = tau * h;
  return x > 0 ? g * (-std::expm1(-x)) / tau : g * h;
}

struct LocalError {
  double e = 0, d = 0;
};

// The leading terms of a smooth segment's local errors (the header's table), and the next ones
// where the depth varies fast across the segment (a thick medium: tau'' h and tau' h against u'').
LocalError smooth_segment(const RuleSegment& seg, const FieldOnSegment& on, const TransferFunction& tf,
                          SegmentRule rule) {
  const double h = seg.b - seg.a, h2 = h * h, h3 = h2 * h;
  const FieldDerivatives f = on.at(seg.m);
  const TransferSegment branch = tf.segment(f.f);
  const double g1 = branch.first.slope, t1 = branch.second.slope;
  const double u1 = g1 * f.d1, u2 = g1 * f.d2, tau1 = t1 * f.d1, tau2 = t1 * f.d2;
  if (is_segment_rule(rule)) {
    // int (u - u^) w^ with u - u^ = u''/2 (x^2 - h^2/4), and u int (w - w^) with
    // int_{-h/2}^{x} (tau - tau^) = tau''/2 ((x^3 + h^3/8)/3 - h^2/4 (x + h/2)).
    const Moments moment = moments(seg.tau_a, (seg.tau_b - seg.tau_a) / h, h);
    const double* m = moment.m;
    const double u = 0.5 * (seg.g_a + seg.g_b);
    const double interpolation = 0.5 * u2 * (m[2] - 0.25 * h2 * m[0]);
    const double attenuation = -0.5 * u * tau2 * ((m[3] + h3 / 8 * m[0]) / 3 - 0.25 * h2 * (m[1] + 0.5 * h * m[0]));
    const double linear = linear_piece(h, seg.g_a, seg.g_b, seg.tau_a, seg.tau_b).emission;
    return {interpolation + attenuation + (linear - seg.emission), -tau2 * h3 / 12};
  }
  // int (u - u_m) w and u_m int (w - w_m): int_{-h/2}^{x} (tau - tau_m) = tau' (x^2 - h^2/4)/2
  // + tau'' (x^3 + h^3/8)/6.
  const Moments moment = moments(seg.tau_m, 0, h);
  const double* m = moment.m;
  const double u = seg.g_m;
  const double e = u1 * m[1] + 0.5 * u2 * m[2] - 0.5 * u * tau1 * (m[2] - 0.25 * h2 * m[0]) -
                   u * tau2 / 6 * (m[3] + h3 / 8 * m[0]) - 0.5 * u1 * tau1 * (m[3] - 0.25 * h2 * m[1]);
  const double constant = constant_emission(seg.g_m, seg.tau_m, h);
  return {e + (constant - seg.emission), tau2 * h3 / 24};
}

// sum |c_n|, n >= 4, of f's proxy on a smooth segment: the part of f the Taylor terms leave out
// (a segment that needed more than one proxy has a feature shorter than itself: not resolved).
double beyond_cubic(const FieldOnSegment& on) {
  const RayPanel& p = on.panels.front();
  double high = 0;
  for (int n = 4; n < p.size(); ++n) high += std::abs(p.coefficients[n]);
  return std::max(0.0, high - p.error - p.noise);  // the proxy's own error is not a feature
}

// One segment's terms of the error scale and of the neglected part: emission-like (times T_k) and
// depth-like (times the light behind the segment, known at the end).
struct SegmentScale {
  double transmittance = 0, emission = 0;       // T_k, E_k T_k
  double scale_e = 0, scale_d = 0, neglected_e = 0, neglected_d = 0;
  bool resolved = true;
};

void add_scales(const std::vector<SegmentScale>& parts, double background_light, DiscreteErrorEstimate& out) {
  double behind = background_light;
  for (auto k = parts.rbegin(); k != parts.rend(); ++k) {
    out.scale += k->scale_e * k->transmittance + k->scale_d * behind;
    out.neglected += k->neglected_e * k->transmittance + k->neglected_d * behind;
    behind += k->emission;
    out.asymptotic = out.asymptotic && k->resolved;
  }
  out.asymptotic = out.asymptotic && out.neglected <= kAsymptoticShare * out.scale && out.thickest <= kAsymptoticDepth;
}

template <ScalarField F>
DiscreteErrorEstimate estimate_for(const F& field, const Scene& scene, const Ray& ray, const DiscreteConfig& config) {
  DiscreteErrorEstimate out;
  const auto iv = clip(ray, scene.box);
  if (!iv) return out;  // the raycast returns the background exactly
  const TransferFunction& tf = scene.transfer;
  double phi = 0, depth_error = 0, minus = 0;  // Phi^_k, D_k, I - I_h
  LightFromAbove light;  // I from above, as the bound's
  double discrete = 0;   // I_h
  std::vector<SegmentScale> scales;
  const long samples = for_each_rule_segment(field, ray, tf, config, *iv, scene.box, [&](const RuleSegment& seg) {
    const double ia = std::max(seg.a, iv->t0), ib = std::min(seg.b, iv->t1);
    LocalError local;
    SegmentScale part;
    part.transmittance = std::exp(-phi);
    if (ib > ia) {
      const FieldOnSegment on = field_on(field, ray, ia, ib);
      out.evaluations += on.evaluations;
      const OpticsOnSegment optics = optics_on(tf, on, 0);
      light.add(optics.g.hi, std::max(0.0, optics.tau.lo), ib - ia);
      const bool smooth = !seg.gap && ia == seg.a && ib == seg.b && optics.smooth;
      if (smooth) {
        local = smooth_segment(seg, on, tf, config.rule);
        part.resolved = on.panels.size() == 1;
        out.thickest = std::max(out.thickest, (seg.b - seg.a) * std::max({seg.tau_a, seg.tau_b, seg.tau_m}));
        const double high = beyond_cubic(on) * (seg.b - seg.a);
        const TransferSegment branch = tf.segment(on.at(0.5 * (seg.a + seg.b)).f);
        part.neglected_e = std::abs(branch.first.slope) * high;
        part.neglected_d = std::abs(branch.second.slope) * high;
      } else {
        const Local exact = exact_on(on, tf);
        local = {exact.emission - seg.emission, exact.depth - seg.depth};
        ++out.exact_segments;
      }
    } else {
      local = {-seg.emission, -seg.depth};  // wholly outside: no light there
    }
    part.emission = seg.emission * part.transmittance;
    discrete += part.emission;
    part.scale_e = std::abs(local.e), part.scale_d = std::abs(local.d);
    scales.push_back(part);
    const double transmittance = part.transmittance;
    minus += local.e * transmittance * std::exp(-depth_error) + seg.emission * transmittance * std::expm1(-depth_error);
    phi += seg.depth;
    depth_error += local.d;
    ++out.segments;
  });
  out.evaluations += samples;
  minus += scene.background * std::exp(-phi) * std::expm1(-depth_error);
  out.error = -minus;
  // I_h - I with 0 <= I <= its upper bound: an expansion that says more (thick segments the steps do
  // not resolve, where e^-D_k compounds) is cut to what is possible, and is not asymptotic.
  discrete += scene.background * std::exp(-phi);
  const double upper = light.upper(scene.background);
  const double slack = 16 * std::numeric_limits<double>::epsilon() * static_cast<double>(out.segments + 1) * (discrete + upper);
  const double clamped = std::clamp(out.error, std::min(0.0, discrete - upper) - slack, discrete + slack);
  if (clamped != out.error) out.asymptotic = false;
  out.error = clamped;
  add_scales(scales, scene.background * std::exp(-phi), out);
  return out;
}

}  // namespace

DiscreteErrorEstimate estimate_discrete_error(const Scene& scene, const Ray& ray, const DiscreteConfig& config) {
  validate(config, std::holds_alternative<GridField>(scene.field), scene.transfer);
  DiscreteErrorEstimate out;
  out.unavailable = why_no_error_bound(scene, config);
  if (!out.available()) return out;
  const DiscreteConfig base = analysed_configuration(config);
  out = visit_field(scene, [&](const auto& field) { return estimate_for(field, scene, ray, base); });
  if (outside_segment_analysis(config).empty()) return out;
  out.cast_difference = cast_difference(scene, ray, config, base, out.evaluations);
  out.error += out.cast_difference;
  return out;
}

}  // namespace vrv
