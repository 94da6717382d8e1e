#pragma once
// The expected error of a discrete raycast of one ray, before the reference: value - I, signed,
// from the rule and the field along the ray (docs/error-bounds.md, "Estimates").
//
// Per segment k (lib/rule_segments.h) the local errors e_k = E*_k - E_k (emission) and
// d_k = dPhi*_k - dPhi^_k (depth) are, where g(f) and tau(f) are smooth on the segment, their
// leading Taylor terms about the sample (sample rules) or midpoint (segment rules), x = s - m,
// with the next terms through tau' h and tau'' h that a thick medium needs (docs/error-bounds.md):
//   alpha      e = u' M1 + u''/2 M2 - u tau'/2 (M2 - h^2/4 M0) - ...,   d = tau'' h^3/24
//   riemann    alpha's, plus the exact (1 - e^-tau h)/tau - h times g (its first-order term)
//   exact_linear  e = u''/2 (M2 - h^2/4 M0) - ...,   d = -tau'' h^3/12
//   trapezoid  exact_linear's, plus the exact difference of the two rules' emissions
// with M_n = int x^n w dx (w: the rule's transmittance across the segment); elsewhere (a
// transfer-function breakpoint or field break in the segment, the ends of the clipped range) the
// segment's exact integrals on the proxy, cut at the crossings (Gauss-Legendre).  The global error
// follows exactly from the local ones:
//   I - I_h = sum_k e_k P^_k e^-D_k + sum_k E_k P^_k (e^-D_k - 1) + I0 P^_K (e^-D_K - 1),
// D_k = sum_{j<k} d_j (signed).  Within 0.5% of the measured error (median) where the steps
// resolve the field; where they do not, still the sum of its segments' local errors, each less
// exact (tests/lib/discrete_error_estimate_test.cpp).
#include <string>

#include "lib/discrete_error_bound.h"
#include "lib/discrete_raycast.h"
#include "lib/geometry.h"
#include "lib/scene.h"

namespace vrv {

struct DiscreteErrorEstimate {
  std::string unavailable;  // why none is made (as DiscreteErrorBound::unavailable); empty when made
  double error = 0;         // expected value - I (signed)
  long segments = 0;
  long exact_segments = 0;  // of which integrated on the proxy (breakpoints, breaks, ends)
  // The error the ray would have if its segments' errors did not cancel: sum_k |e_k| T_k +
  // |d_k| (the light behind segment k); |error| <= scale up to the estimate's own miss.
  double scale = 0;
  // The part of f beyond its cubic Taylor terms, as an error: sum over the segments estimated by
  // their leading terms of (|g'| T_k + |tau'| (light behind)) h sum_{n >= 4} |c_n| (c: f's
  // Chebyshev proxy on the segment).  Small against `scale` when the steps are shorter than the
  // field's features.
  double neglected = 0;
  // The largest optical depth of a segment estimated by its Taylor terms (they are expansions in
  // the segment's depth variation as much as in h).
  double thickest = 0;
  // The asymptotic range, where the estimate is the error's leading terms: every proxy resolved at
  // 17 or 33 nodes, neglected <= kAsymptoticShare x scale and thickest <= kAsymptoticDepth.  There
  // the estimate misses by at most 2% of `scale` (99th percentile; 0.13% at the 90th), elsewhere by
  // 5% (90th) to 30% (99th): tests/lib/discrete_error_estimate_test.cpp.
  bool asymptotic = true;
  long evaluations = 0;     // field evaluations (proxies and samples)
  // I_h - I_h(analysed_configuration), cast exactly (lib/discrete_error_bound.h): included in
  // `error`; the rest (scale, asymptotic, ...) describes the analysed configuration.
  double cast_difference = 0;
  bool available() const { return unavailable.empty(); }
};

inline constexpr double kAsymptoticShare = 0.01;
inline constexpr double kAsymptoticDepth = 2;

// Field evaluations of a discrete raycast with its bound and estimate, per sample of the raycast
// alone (each about kErrorBoundEvaluationsPerSegment): `vrv ray --bound`'s and Python's
// discrete(bound=True)'s work estimate.
inline constexpr double kPredictedRaycastWorkFactor = 1 + 2 * (kErrorBoundEvaluationsPerSegment + 2);

// Throws what discrete_raycast throws for an invalid configuration.
DiscreteErrorEstimate estimate_discrete_error(const Scene& scene, const Ray& ray, const DiscreteConfig& config);

}  // namespace vrv
