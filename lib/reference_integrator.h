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
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <vector>

#include "analytic/piece_integrals.h"
#include "lib/chebyshev.h"
#include "lib/field.h"
#include "lib/geometry.h"
#include "lib/ray_accumulator.h"
#include "lib/ray_panel.h"
#include "lib/scene.h"
#include "lib/shading_weight.h"
#include "lib/transfer_function.h"

namespace vrv {

// Throws OptionError (Option::tol) unless tol is positive and finite: the one check of every
// reference's tolerance (grey, colour, projections, verify's, plan's and the commands').
void check_tolerance(double tol);
// check_tolerance(options.tol).
void validate(const ReferenceOptions& options);

namespace detail {

// Work cap per ray: past it the rest of the ray is bounded (RayAccumulator::give_up).
inline constexpr long kMaxEvaluations = 1'000'000;

// The field's rounding level on [a, b] of the ray (its coordinates' size matters far out).
template <ScalarField F>
double panel_noise(const F& field, const Ray& ray, double a, double b) {
  return field_value_noise(field, Vec3(ray.at(a).cwiseAbs().cwiseMax(ray.at(b).cwiseAbs())));
}

// Fits `panel` anew on [a, b], reusing its storage: a grid ray fits one panel per cell, and two
// allocations per cell were a tenth of the grid reference's time.
template <ScalarField F>
void refit_panel(const F& field, const Ray& ray, double a, double b, int n, long& evaluations, RayPanel& panel) {
  const ChebyshevRule& rule = ChebyshevRule::get(n);
  panel.a = a, panel.b = b;
  panel.values.resize(n);
  panel.coefficients.resize(n);
  panel.forget_derived();
  for (int j = 0; j < n; ++j) panel.values[j] = field.value(ray.at(panel.t_of(rule.node(j))));
  evaluations += n;
  rule.coefficients(panel.values, panel.coefficients);
  // The error is what the coefficients show; the field's absolute noise only decides when
  // splitting has stopped helping (it would otherwise inflate every panel's estimate by the
  // worst-case rounding, which the tail already measures where it matters), and how well a
  // jump's crossing can be placed.
  panel.error = chebyshev_accuracy(panel.coefficients).error;
  panel.noise = panel_noise(field, ray, a, b);
  panel.resolved = chebyshev_accuracy(panel.coefficients, panel.noise).resolved;
}

template <ScalarField F>
RayPanel fit_panel(const F& field, const Ray& ray, double a, double b, int n, long& evaluations) {
  RayPanel panel;
  refit_panel(field, ray, a, b, n, evaluations, panel);
  return panel;
}

// Nodes of a panel of an analytic field (resolve_smooth).
inline constexpr int kPanelNodes = 33;

// Splits [a, b] until the proxy meets the field tolerance, consuming panels in ray order.
template <ScalarField F, class Accumulator>
void resolve_smooth(const F& field, const Ray& ray, double a, double b, int level,
                    Accumulator& acc, long& evaluations) {
  constexpr int n = kPanelNodes;
  constexpr int max_level = 30;
  if (acc.stopped()) return;
  RayPanel panel = fit_panel(field, ray, a, b, n, evaluations);
  const ChebyshevAccuracy check = chebyshev_accuracy(panel.coefficients, panel.noise);
  const bool good = check.resolved &&
                    (check.at_rounding || (panel.error <= acc.field_tolerance() && acc.jumps_located(panel)));
  if (!good && evaluations >= kMaxEvaluations) {
    // An unresolved panel's error is only a guess: bound the rest of the ray instead.
    acc.give_up(a);
    return;
  }
  if (!good && level < max_level) {
    const double m = 0.5 * (a + b);
    resolve_smooth(field, ray, a, m, level + 1, acc, evaluations);
    resolve_smooth(field, ray, m, b, level + 1, acc, evaluations);
    return;
  }
  if (!good) acc.note_cap();
  acc.consume(panel);
}

// The first panels of a stretch are `count` equal parts sized for the field's global
// bandwidth; where the field is locally slower (field_bandwidth_between), several of them, from
// part k on, become one panel spanning at most `phase` radians of the local bound.  The largest
// such m (the bound only grows with the stretch, so the test is monotone in m); 1 where the
// field is as fast as its global bound, which keeps those panels (and values) as they were.
// Merged panels raise the estimate's rounding floor (on the convergence scene, 2000 rays: largest
// estimate 5.4e-14 -> 1.5e-13, and 149 rays missed tol 1e-13 that met it before), so they are
// used where that floor is far below the tolerance (tol >= kMergeTolerance: the reference image
// at 1e-10 costs a third) or where the global sizing spends many panels (at least
// kMinPartsToMerge: the fM = 24 axis ray, 29,535 -> 198 evaluations).  Elsewhere (the few
// panels of an ordinary ray at tol 1e-12) values stay bitwise as they were.
inline constexpr double kMinPartsToMerge = 64;
inline constexpr double kMergeTolerance = 1e-11;
template <ScalarField F, class At>
double panels_to_merge(const F& field, const Ray& ray, const At& at, double count, double k,
                       double phase, double tol) {
  if constexpr (!requires(const Vec3& p) { field.bandwidth_between(p, p); }) return 1;
  if (count < kMinPartsToMerge && tol < kMergeTolerance) return 1;
  const double left = count - k;
  const auto fits = [&](double m) {
    const double t0 = at(k), t1 = at(k + m);
    return (t1 - t0) * field_bandwidth_between(field, ray.at(t0), ray.at(t1)) <= phase;
  };
  if (!(left >= 2) || !fits(2)) return 1;
  double lo = 2;  // fits
  while (2 * lo <= left && fits(2 * lo)) lo *= 2;
  double hi = std::min(2 * lo, left);
  if (hi > lo && fits(hi)) return hi;
  while (hi - lo > 1) {  // fits(lo), !fits(hi)
    const double mid = std::floor(0.5 * (lo + hi));
    (fits(mid) ? lo : hi) = mid;
  }
  return lo;
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

// The first panels of a stretch [a, b]: equal parts at most first_panel_phase(tol) radians of
// the field's bandwidth long (the whole stretch for a field without one), at least one.  A double,
// not an int: a long ray or a huge bandwidth asks for more panels than any integer holds.
inline double first_panel_length(double bandwidth, double tol, double a, double b) {
  return bandwidth > 0 ? first_panel_phase(tol) / bandwidth : b - a;
}
inline double first_panel_count(double h0, double a, double b) { return std::max(1.0, std::ceil((b - a) / h0)); }

namespace detail {

// Whether the field can hold empty space at all: false when the transfer function is transparent
// at no value its nodes reach (widened as below), so no cell or brick need be looked at (a scene
// without empty space pays nothing for the search).  `tf`: anything with transparent_on(lo, hi)
// and transparent_somewhere(lo, hi) (a transfer function, or every channel of an RGB one); `acc`:
// a RayAccumulator<N> or anything with its interface.
template <ScalarField F, class Transparency, class Accumulator>
bool may_hold_empty_space(const F& field, const Transparency& tf, const Accumulator& acc) {
  if constexpr (requires { field.node_range(); }) {
    const auto [lo, hi] = field.node_range();
    const double margin = field.value_noise() + acc.position_error();
    return tf.transparent_somewhere(lo - margin, hi + margin);
  }
  return true;
}

// Empty space, skipped exactly: a grid cell whose nodes (widened by the field's rounding and the
// far ray's position error) all map to g = tau = 0 adds neither light nor depth.
template <ScalarField F, class Transparency, class Accumulator>
bool empty_stretch(const F& field, const Ray& ray, double a, double b, const Transparency& tf,
                   const Accumulator& acc) {
  if constexpr (requires { field.node_range_between(ray.at(a), ray.at(b)); }) {
    const auto [lo, hi] = field.node_range_between(ray.at(a), ray.at(b));
    const double margin = field.value_noise() + acc.position_error();
    return tf.transparent_on(lo - margin, hi + margin);
  }
  return false;
}

// The field's breaks along iv, sorted; where the field knows empty space in bulk (a grid's
// bricks), each transparent stretch is one piece listed in `skipped` (in order, each starting at a
// cut) and no break is made inside it.  Elsewhere the breaks are the field's own, to the bit.
template <ScalarField F, class Transparency, class Accumulator>
std::vector<double> cuts_around_empty_space(const F& field, const Ray& ray, Interval iv, const Transparency& tf,
                                            const Accumulator& acc, bool may_be_empty, std::vector<Interval>& skipped) {
  if constexpr (requires { F::kBrickCells; }) {
    if (may_be_empty) {
      const double margin = field.value_noise() + acc.position_error();
      field.append_transparent_spans(
          ray, iv, [&](double lo, double hi) { return tf.transparent_on(lo - margin, hi + margin); }, skipped);
    }
  }
  std::vector<double> cuts{iv.t0};
  double from = iv.t0;
  const auto breaks_up_to = [&](double to) {
    if (to > from) {
      field.append_breaks(ray, Interval{from, to}, cuts);
      cuts.push_back(to);
    }
  };
  for (const Interval& s : skipped) {
    breaks_up_to(s.t0);
    cuts.push_back(s.t1);
    from = s.t1;
  }
  breaks_up_to(iv.t1);
  if (!std::is_sorted(cuts.begin(), cuts.end())) std::sort(cuts.begin(), cuts.end());
  return cuts;
}

// One pass over the clipped ray at options.tol: panels fitted to the field and consumed by `acc`
// in ray order, refined until `acc` accepts them.  Returns the field evaluations.
template <ScalarField F, class Transparency, class Accumulator>
long walk_ray(const F& field, const RayFrame& frame, const Transparency& tf, const ReferenceOptions& options,
              Accumulator& acc) {
  const Ray& local = frame.local;
  const Interval iv = frame.iv;
  std::vector<Interval> skipped;
  const bool may_be_empty = may_hold_empty_space(field, tf, acc);
  const std::vector<double> cuts = cuts_around_empty_space(field, local, iv, tf, acc, may_be_empty, skipped);
  std::size_t next_skipped = 0;
  long evaluations = 0;
  const int degree = field.degree_along_ray();
  RayPanel cell;  // a known-degree field's panels, one per stretch between breaks
  for (std::size_t i = 0; i + 1 < cuts.size() && !acc.stopped(); ++i) {
    const double a = cuts[i], b = cuts[i + 1];
    if (!(b > a)) continue;
    if (next_skipped < skipped.size() && a == skipped[next_skipped].t0) {
      ++next_skipped;  // one piece, transparent brick by brick
      continue;
    }
    if (degree >= 0) {
      if (evaluations >= kMaxEvaluations) {
        acc.give_up(a);
        break;
      }
      if (may_be_empty && empty_stretch(field, local, a, b, tf, acc)) continue;
      refit_panel(field, local, a, b, degree + 1, evaluations, cell);
      acc.consume(cell);
      continue;
    }
    const double phase = first_panel_phase(options.tol);
    const double h0 = first_panel_length(field.bandwidth(), options.tol, a, b);
    // The work cap ends the loop long before k loses integer precision.
    const double count = first_panel_count(h0, a, b);
    if (count > 1 && h0 < 16 * std::numeric_limits<double>::epsilon() * std::max(std::abs(a), std::abs(b))) {
      acc.give_up(a);  // the field varies faster than positions along the ray can resolve
      break;
    }
    const auto at = [&](double k) { return k >= count ? b : a + (b - a) * k / count; };
    for (double k = 0; k < count && !acc.stopped();) {
      if (evaluations >= detail::kMaxEvaluations) {
        acc.give_up(at(k));
        break;
      }
      const double m = detail::panels_to_merge(field, local, at, count, k, phase, options.tol);
      detail::resolve_smooth(field, local, at(k), at(k + m), 0, acc, evaluations);
      k += m;
    }
  }
  return evaluations;
}

// The emission's weight for `shading` on this ray, or none when the scene does not shade (one
// allocation per shaded ray; a field without a gradient cannot shade).
template <ScalarField F>
std::unique_ptr<EmissionWeight> shading_on(const F& field, const RayFrame& frame, const Shading* shading) {
  if (!shading) return nullptr;
  if constexpr (GradientField<F>) return std::make_unique<FieldShading<F>>(field, frame.local, *shading);
  else throw std::invalid_argument("shading: this field has no gradient to shade with");
}

// A stretch is empty only where every channel is transparent.
template <std::size_t N>
struct AllChannelsTransparent {
  std::span<const ReferenceChannel, N> channels;
  bool transparent_on(double lo, double hi) const {
    for (const ReferenceChannel& c : channels)
      if (!c.transfer->transparent_on(lo, hi)) return false;
    return true;
  }
  // Every channel transparent somewhere in [lo, hi] (not necessarily at one value: a gate may say
  // yes where no stretch is empty, never no where one is).
  bool transparent_somewhere(double lo, double hi) const {
    for (const ReferenceChannel& c : channels)
      if (!c.transfer->transparent_somewhere(lo, hi)) return false;
    return true;
  }
};

// One walk along the ray for N channels sharing one extinction: each channel's result, each
// counting the walk's evaluations.
template <int N, ScalarField F>
std::array<ReferenceResult, N> integrate_pass(const F& field, const RayFrame& frame,
                                              std::span<const ReferenceChannel, N> channels,
                                              const ReferenceOptions& options, const Shading* shading) {
  const auto weight = shading_on(field, frame, shading);
  RayAccumulator<N> acc(channels, options, frame.iv, field_change_within(field, frame.position_error), weight.get());
  const long evaluations = walk_ray(field, frame, AllChannelsTransparent<N>{channels}, options, acc);
  std::array<ReferenceResult, N> results;
  for (int c = 0; c < N; ++c) {
    results[c] = acc.finish(c);
    results[c].t_entry = frame.t_entry();
    results[c].t_exit = frame.t_exit();
    results[c].evaluations = evaluations;
  }
  return results;
}

// A tolerance missed by at most kRetryWithin x is retried once at kRetryTolerance x it.  The
// shares hold what refinement shrinks to about tol, so an estimate far above it is rounding,
// which a retry cannot shrink (it would only double the work).
inline constexpr double kRetryWithin = 4;
inline constexpr double kRetryTolerance = 0.125;

// The rounding terms of the estimate, which no refinement shrinks, can leave less of tol than the
// shares assume for the terms refinement does shrink (field, quadrature): a pass that missed tol by
// a little is worth one more with those held to a fraction of tol.
inline bool worth_retry(const ReferenceResult& first, double tol) {
  return !first.tolerance_met && !first.capped && first.error_estimate <= kRetryWithin * tol;
}
inline ReferenceOptions retry_options(ReferenceOptions options) {
  options.tol *= kRetryTolerance;
  return options;
}
// Of the two passes, the smaller estimate, both passes' work counted.
inline ReferenceResult better_pass(const ReferenceResult& first, const ReferenceResult& second, double tol) {
  ReferenceResult kept = second.error_estimate < first.error_estimate ? second : first;
  kept.evaluations = first.evaluations + second.evaluations;
  kept.tolerance_met = !kept.capped && kept.error_estimate <= tol && std::isfinite(kept.value) &&
                       std::isfinite(kept.error_estimate);
  return kept;
}

// integrate_pass with the retry: when any channel missed its tolerance by a little, all are
// integrated once more at the tighter tolerance (the panels are shared) and each keeps its
// smaller estimate.
template <int N, ScalarField F>
std::array<ReferenceResult, N> integrate_passes(const F& field, const RayFrame& frame,
                                                std::span<const ReferenceChannel, N> channels,
                                                const ReferenceOptions& options, const Shading* shading) {
  std::array<ReferenceResult, N> first = integrate_pass<N>(field, frame, channels, options, shading);
  bool retry = false;
  for (const ReferenceResult& r : first) retry = retry || worth_retry(r, options.tol);
  if (!retry) return first;
  const std::array<ReferenceResult, N> second =
      integrate_pass<N>(field, frame, channels, retry_options(options), shading);
  for (int c = 0; c < N; ++c) first[c] = better_pass(first[c], second[c], options.tol);
  return first;
}

}  // namespace detail

// shading: a factor on the emission (lib/shading.h), or none.
template <ScalarField F>
ReferenceResult integrate_reference(const F& field, const Box& box, const TransferFunction& tf,
                                    double background, const Ray& ray,
                                    const ReferenceOptions& options = {}, const Shading* shading = nullptr) {
  // Everything works in the ray's own frame (positions near the box).
  const auto frame = clip_in_frame(ray, box);
  if (!frame) {
    ReferenceResult miss;
    miss.value = background;
    return miss;
  }
  const std::array<ReferenceChannel, 1> channel{{{&tf, background}}};
  return detail::integrate_passes<1>(field, *frame, std::span(channel), options, shading)[0];
}

// The scene's field, dispatched to its concrete type.
ReferenceResult integrate_reference(const Scene& scene, const Ray& ray,
                                    const ReferenceOptions& options = {});

}  // namespace vrv
