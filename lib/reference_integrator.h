#pragma once
// The reference value of the emission-absorption integral along a ray,
//   I = int_{t0}^{t1} g(f(s)) exp(-int_{t0}^{s} tau(f(u)) du) ds + I0 exp(-int_{t0}^{t1} tau),
// to an absolute tolerance, with an error estimate meant never to be exceeded.
//
// Method (docs/reference-integrator.md): the ray is cut at structural breaks (grid cell
// faces); the field along each stretch becomes Chebyshev panels (exact for known-degree
// fields, adaptive to the tolerance for analytic ones); each panel is cut again where f
// crosses a transfer-function control value, so g and tau are smooth on every piece; each
// piece is then done by the cheapest exact route: closed forms for constant and linear
// pieces, I = kappa (1 - e^-Phi) when g = kappa tau, else adaptive Clenshaw-Curtis on
// g e^-Phi with Phi integrated spectrally.  Transmittance is kept as the optical depth Phi.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "analytic/piece_integrals.h"
#include "lib/chebyshev.h"
#include "lib/field.h"
#include "lib/geometry.h"
#include "lib/ray_panel.h"
#include "lib/scene.h"
#include "lib/transfer_function.h"

namespace vrv {

struct ReferenceOptions {
  double tol = 1e-12;  // absolute tolerance on I
};

struct ReferenceResult {
  double value = 0;           // I
  double error_estimate = 0;  // bound on |I - value| (absolute)
  long evaluations = 0;       // field evaluations
  bool hit = false;           // the ray meets the box
  double t_entry = 0;         // clipped parameter range (world length along the unit direction)
  double t_exit = 0;
  double optical_depth = 0;   // int tau over [t_entry, t_exit]
  bool tolerance_met = true;  // false when the work cap was reached or the estimate exceeds the tolerance
};

namespace detail {

// Accumulates one ray front to back: optical depth so far (log transmittance), value, error.
class RayAccumulator {
 public:
  RayAccumulator(const TransferFunction& tf, double background, double tol, Interval iv);

  // Field error allowed on a panel starting now, so that its effect on I stays in budget.
  double field_tolerance() const;
  // Integrates g e^-Phi over the panel (cut at transfer-function crossings) and adds the
  // panel's own proxy error to the estimate.
  void consume(const RayPanel& panel);
  ReferenceResult finish() const;

 private:
  void integrate_piece(const RayPanel& panel, double c, double d, const TransferSegment& seg);
  // Adaptive Clenshaw-Curtis on [c, d]; `depth_only` skips the emission.
  void integrate_spectral(const RayPanel& panel, double c, double d, const TransferSegment& seg,
                          bool depth_only, int level);
  void add(const PieceIntegral& piece);
  void check_termination(double t);
  double sensitivity_after(double t) const;  // a priori bound on |dI / dPhi| at t
  // An uncertainty dPhi in the optical depth here scales everything behind by e^-dPhi, so it
  // costs dPhi times the part of I that comes after this point: known once the ray is done.
  void book_depth_error(double dphi);

  const TransferFunction& tf_;
  double background_;
  double tol_;
  Interval iv_;
  double phi_ = 0;
  double value_ = 0;
  double error_ = 0;
  bool emission_done_ = false;
  long spectral_pieces_ = 0;
  double depth_error_ = 0;           // sum of dPhi_i
  double depth_error_weighted_ = 0;  // sum of dPhi_i * (value before i)
  std::vector<Crossing> crossings_;
};

template <ScalarField F>
RayPanel fit_panel(const F& field, const Ray& ray, double a, double b, int n, long& evaluations) {
  const ChebyshevRule& rule = ChebyshevRule::get(n);
  RayPanel panel{a, b, std::vector<double>(n), std::vector<double>(n), 0, true};
  for (int j = 0; j < n; ++j) panel.values[j] = field.value(ray.at(panel.t_of(rule.node(j))));
  evaluations += n;
  rule.coefficients(panel.values, panel.coefficients);
  // The error is what the coefficients show; the field's absolute noise only decides when
  // splitting has stopped helping (it would otherwise inflate every panel's estimate by the
  // worst-case rounding, which the tail already measures where it matters).
  panel.error = chebyshev_accuracy(panel.coefficients).error;
  panel.resolved = chebyshev_accuracy(panel.coefficients, field_value_noise(field)).resolved;
  return panel;
}

// Splits [a, b] until the proxy meets the field tolerance, consuming panels in ray order.
template <ScalarField F>
void resolve_smooth(const F& field, const Ray& ray, double a, double b, int level,
                    RayAccumulator& acc, long& evaluations) {
  constexpr int n = 33;
  constexpr int max_level = 30;
  constexpr long max_evaluations = 1'000'000;  // work cap per ray, as for the quadrature
  RayPanel panel = fit_panel(field, ray, a, b, n, evaluations);
  const ChebyshevAccuracy check = chebyshev_accuracy(panel.coefficients, field_value_noise(field));
  const bool good = check.resolved && (check.at_rounding || panel.error <= acc.field_tolerance());
  if (!good && level < max_level && evaluations < max_evaluations) {
    const double m = 0.5 * (a + b);
    resolve_smooth(field, ray, a, m, level + 1, acc, evaluations);
    resolve_smooth(field, ray, m, b, level + 1, acc, evaluations);
    return;
  }
  acc.consume(panel);
}

}  // namespace detail

// How many radians of the field's fastest oscillation a first panel spans: 33-point panels
// resolve cos(w t) to ~1e-14 while w h <= ~18.
inline constexpr double kPanelPhase = 16;

// The first panel's phase for a tolerance: kPanelPhase up to 1e-10; looser tolerances allow
// longer panels.  The 33-point coefficients of cos(w t) fall like (w h / 4)^33 / 33!, so the
// phase that keeps them under tol grows like tol^(1/33) (x 1.75 at 1e-2).  Only the first guess:
// panels are still halved until their tail meets the field tolerance.
inline double first_panel_phase(double tol) {
  return kPanelPhase * std::pow(std::clamp(tol, 1e-10, 1e-1) / 1e-10, 1.0 / 33);
}

template <ScalarField F>
ReferenceResult integrate_reference(const F& field, const Box& box, const TransferFunction& tf,
                                    double background, const Ray& ray,
                                    const ReferenceOptions& options = {}) {
  const auto iv = clip(ray, box);
  if (!iv) {
    ReferenceResult miss;
    miss.value = background;
    return miss;
  }
  std::vector<double> cuts{iv->t0};
  field.append_breaks(ray, *iv, cuts);
  cuts.push_back(iv->t1);
  std::sort(cuts.begin(), cuts.end());

  detail::RayAccumulator acc(tf, background, options.tol, *iv);
  long evaluations = 0;
  const int degree = field.degree_along_ray();
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    const double a = cuts[i], b = cuts[i + 1];
    if (!(b > a)) continue;
    if (degree >= 0) {
      acc.consume(detail::fit_panel(field, ray, a, b, degree + 1, evaluations));
      continue;
    }
    const double h0 = field.bandwidth() > 0 ? first_panel_phase(options.tol) / field.bandwidth() : b - a;
    const int count = std::max(1, static_cast<int>(std::ceil((b - a) / h0)));
    for (int k = 0; k < count; ++k)
      detail::resolve_smooth(field, ray, a + (b - a) * k / count,
                             k + 1 == count ? b : a + (b - a) * (k + 1) / count, 0, acc,
                             evaluations);
  }
  ReferenceResult result = acc.finish();
  result.evaluations = evaluations;
  result.tolerance_met = result.error_estimate <= options.tol;
  return result;
}

// The scene's field, dispatched to its concrete type.
ReferenceResult integrate_reference(const Scene& scene, const Ray& ray,
                                    const ReferenceOptions& options = {});

}  // namespace vrv
