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
#include <memory>
#include <optional>
#include <stdexcept>
#include <vector>

#include "analytic/piece_integrals.h"
#include "lib/chebyshev.h"
#include "lib/field.h"
#include "lib/geometry.h"
#include "lib/ray_panel.h"
#include "lib/scene.h"
#include "lib/shading_weight.h"
#include "lib/spectral_depth.h"
#include "lib/transfer_function.h"

namespace vrv {

struct ReferenceOptions {
  double tol = 1e-12;  // absolute tolerance on I
  // Stop a ray once e^-Phi (max g x the length still to come + background) is below the
  // termination share of tol: nothing behind can matter (the bound joins the estimate), and
  // optical_depth is then the depth up to there.  False: Phi is carried to the exit.
  bool stop_when_opaque = true;
};

// Throws OptionError (Option::tol) unless tol is positive and finite: the one check of every
// reference's tolerance (grey, colour, projections, verify's, plan's and the commands').
void check_tolerance(double tol);
// check_tolerance(options.tol).
void validate(const ReferenceOptions& options);

struct ReferenceResult {
  double value = 0;           // I
  double error_estimate = 0;  // bound on |I - value| (absolute)
  long evaluations = 0;       // field evaluations
  bool hit = false;           // the ray meets the box
  double t_entry = 0;         // clipped parameter range (world length along the unit direction)
  double t_exit = 0;
  double optical_depth = 0;   // int tau over [t_entry, t_exit], or up to where an opaque ray stopped
  // Stopped where nothing behind could matter any more (stop_when_opaque; the ray became
  // opaque, or emits nothing and has no background): optical_depth is then a lower bound.
  bool stopped_early = false;
  // The estimate is within the tolerance and no work cap was reached (a capped ray still
  // reports an honest, large estimate).  False also for a non-finite value or estimate.
  bool tolerance_met = true;
  // A work cap (evaluations, spectral pieces, halvings) ended the ray or accepted a piece unresolved.
  bool capped = false;
};

namespace detail {

// Accumulates one ray front to back: optical depth so far (log transmittance), value, error.
class RayAccumulator {
 public:
  // position_error: a field error every panel carries on top of its own (the rounding of a
  // far ray's entry point, field_change_within(RayFrame::position_error)).  weight: a factor on
  // the emission (shading, lib/shading_weight.h), or none; it must outlive the accumulator.
  RayAccumulator(const TransferFunction& tf, double background, const ReferenceOptions& options,
                 Interval iv, double position_error = 0, const EmissionWeight* weight = nullptr);

  // Field error allowed on a panel starting now, so that its effect on I stays in budget.
  double field_tolerance() const;
  // Integrates g e^-Phi over the panel (cut at transfer-function crossings) and adds the
  // panel's own proxy error to the estimate.
  void consume(const RayPanel& panel);
  // False where the proxy comes within its error of a jump of the transfer function without
  // crossing it there: the field may cross where the proxy does not, so the panel should be
  // refined (if it cannot be, consume() charges the jump over the whole stretch).
  bool jumps_located(const RayPanel& panel);
  ReferenceResult finish() const;
  // Nothing after this point can matter (opaque), or the work cap ended the ray.
  bool stopped() const { return stopped_; }
  // The work cap is reached at t: the rest of the ray is bounded, not integrated.
  void give_up(double t);
  // A piece or panel was accepted unresolved at a work limit.
  void note_cap() { capped_ = true; }
  // The field error every panel carries (a far ray's rounded entry point).
  double position_error() const { return position_error_; }
  // Depth halves of pieces shared with the other channels of a walk (lib/spectral_depth.h); it
  // must outlive the accumulator and be cleared before each panel.
  void share_depth(SpectralDepthShare* share) { depth_share_ = share; }

 private:
  void integrate_piece(const RayPanel& panel, double c, double d, const TransferSegment& seg);
  // Replaces a closed-form piece's joint charge (the last one) by one per part of it.
  void split_closed_form_joint(const RayPanel& panel, double c, double d, const TransferSegment& seg,
                               double phi0, double value0);
  // A piece that absorbs (nearly) everything, from Phi alone; false when it does not apply.
  bool integrate_opaque_piece(const RayPanel& panel, double c, double d, const TransferSegment& seg);
  // Adaptive Clenshaw-Curtis on [c, d]; `depth_only` skips the emission.
  void integrate_spectral(const RayPanel& panel, double c, double d, const TransferSegment& seg,
                          bool depth_only, int level);
  // One Clenshaw-Curtis rule of n points on [c, d]: the piece's depth, emission and their errors.
  struct SpectralTry {
    double dphi = 0;
    double depth_error = 0;
    double error = 0;
    double emission = 0;
    bool converged = false;
    bool at_rounding = false;
  };
  SpectralTry spectral_try(const RayPanel& panel, double c, double d, const TransferSegment& seg,
                           bool depth_only, int n) const;
  // spectral_try's depth half, computed (into `out`, or a slot of the share) or read from the
  // share; the reference is valid until the share's next slot().
  SpectralDepth& spectral_depth(const RayPanel& panel, double c, double d, const TransferSegment& seg,
                                bool with_phi, const ChebyshevRule& rule, SpectralDepth& out) const;
  void add(const PieceIntegral& piece);
  // Where a field error of the panel's size could put a jump's crossings (JumpBand), from
  // crossings_ (found first); returns whether each band holds exactly one located crossing.
  bool find_jump_bands(const RayPanel& panel);
  // The emission error of the bands from `first` on that start at or before c (reached by the
  // integration), each attenuated at least as much as from its start; returns the next band.
  std::size_t charge_bands(std::size_t first, double c, double panel_transmittance);
  void check_termination(double t);
  // The cuts of a panel: the transfer function's crossings and, with a weight, its switches
  // (a misplaced jump of the weight charged over its uncertainty), sorted, into cuts_.
  void panel_cuts(const RayPanel& panel);
  // max g, max |dg/dv| over all values, times the weight's largest value.
  double max_emission() const { return tf_.max_emission() * shade_max_; }
  double sensitivity_after(double t) const;  // a priori bound on |dI / dPhi| at t
  // An uncertainty dPhi in the optical depth here scales everything behind by e^-dPhi, so it
  // costs dPhi times the part of I that comes after this point: known once the ray is done.
  void book_depth_error(double dphi);
  // Phi += dphi, booking the sum's rounding.
  void advance_depth(double dphi);

  const TransferFunction& tf_;
  const EmissionWeight* weight_;
  SpectralDepthShare* depth_share_ = nullptr;
  double shade_max_ = 1, shade_min_ = 1;  // the weight's range (1 without one)
  std::vector<WeightSwitch> switches_;    // scratch: a panel's switches
  std::vector<double> cuts_;              // scratch: a panel's cuts
  double background_;
  double tol_;
  bool stop_when_opaque_;
  Interval iv_;
  double position_error_;
  double phi_ = 0;
  double transmittance_ = 1;  // e^-Phi, kept with Phi (advance_depth): every piece asks for it several times
  double value_ = 0;
  double error_ = 0;
  bool emission_done_ = false;
  double emission_done_at_ = std::numeric_limits<double>::infinity();  // where it became done
  double stopped_at_ = std::numeric_limits<double>::infinity();        // where the state froze
  bool stopped_ = false;
  bool stopped_early_ = false;
  bool capped_ = false;
  double termination_booked_ = 0;  // error booked by early termination so far
  long spectral_pieces_ = 0;
  double max_extinction_ = 0;        // max tau over all values
  // The least size of v whose rounding the spectral rule charges through the slopes: 1, or the
  // transfer function's largest level where that is below 1 (and then at least the field's
  // noise).  v's rounding is a few ulps of the values it was computed at; a field of 1e-181 with
  // its levels in the same units was charged ulps of 1 times slopes of 1e180 (an estimate of 1e165).
  double value_floor_ = 1;
  // A stretch [u, u + ...] of the current panel where a jump at `level` may be crossed: dt is
  // how far the field's crossing can lie from the one integrated (the stretch's length where
  // none was located).
  struct JumpBand {
    double u = 0;
    double dt = 0;
    double level = 0;
  };
  std::vector<double> jump_levels_;  // the transfer function's breakpoints that are jumps
  std::vector<JumpBand> bands_;
  std::vector<double> breaks_;       // scratch: the panel's monotone parts
  double piece_depth_error_ = 0;     // the field-error part of dPhi booked for the current piece
  TransferFunction::Slopes branch_slopes_;  // |dg/dv|, |dtau/dv| on the current piece's branch
  double depth_error_ = 0;           // sum of dPhi_i
  double depth_error_weighted_ = 0;  // sum of dPhi_i * (value before i)
  std::vector<Crossing> crossings_;
  // A field error at a point changes g there and tau for everything after it: per unit of error
  // I moves by dg T - dtau R (T the transmittance there, R the light still to come, background
  // included).  The two terms cancel where g and tau rise together (a thick medium of constant
  // g / tau does not care where it starts; charged apart, they made estimates 10^3 x the
  // error), so pieces of affine branches and jumps' bands are charged jointly, in finish(), once
  // R is known: over the ranges T and R can take there.
  struct JointCharge {
    double size = 0;                      // field error x length (a piece), the band's width (a jump)
    double dg = 0, dtau = 0;              // signed slopes (a piece), signed jumps (a band)
    double t_lo = 0, t_hi = 0;            // transmittance where it applies
    double before_lo = 0, before_hi = 0;  // the emission accumulated before that point
    double s_lo = 1, s_hi = 1;            // the range of the emission's weight there
  };
  std::vector<JointCharge> joint_;
  JointCharge* piece_joint_ = nullptr;  // the current piece's, while it is integrated
  double joint_error(double value, double other_error) const;
};

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
// a RayAccumulator or anything with its interface (ChannelAccumulators).
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
// allocation per shaded ray; a field without a gradient cannot shade); `channels` weigh with it.
template <ScalarField F>
std::unique_ptr<EmissionWeight> shading_on(const F& field, const RayFrame& frame, const Shading* shading,
                                           int channels = 1) {
  if (!shading) return nullptr;
  if constexpr (GradientField<F>) return std::make_unique<FieldShading<F>>(field, frame.local, *shading, channels);
  else throw std::invalid_argument("shading: this field has no gradient to shade with");
}

template <ScalarField F>
ReferenceResult integrate_pass(const F& field, const RayFrame& frame, const TransferFunction& tf,
                               double background, const ReferenceOptions& options, const Shading* shading = nullptr) {
  const auto weight = shading_on(field, frame, shading);
  RayAccumulator acc(tf, background, options, frame.iv, field_change_within(field, frame.position_error),
                     weight.get());
  const long evaluations = walk_ray(field, frame, tf, options, acc);
  ReferenceResult result = acc.finish();
  result.t_entry = frame.t_entry();
  result.t_exit = frame.t_exit();
  result.evaluations = evaluations;
  return result;
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
  const ReferenceResult first = detail::integrate_pass(field, *frame, tf, background, options, shading);
  if (!detail::worth_retry(first, options.tol)) return first;
  const ReferenceResult second =
      detail::integrate_pass(field, *frame, tf, background, detail::retry_options(options), shading);
  return detail::better_pass(first, second, options.tol);
}

// The scene's field, dispatched to its concrete type.
ReferenceResult integrate_reference(const Scene& scene, const Ray& ray,
                                    const ReferenceOptions& options = {});

}  // namespace vrv
