#pragma once
// An a-priori bound on the error of a discrete raycast of one ray: |I - I_h| <= bound, derived
// from the rule and the field along the ray, without the reference (docs/error-bounds.md).
//
// Every rule turns the ray into segments k, each an emission E_k and a depth dPhi^_k
// (transparency e^-dPhi^_k).  With the exact segment values E*_k, dPhi*_k and the depth before
// segment k (Phi*_k, Phi^_k), telescoping the front-to-back sum gives
//   I - I_h = sum_k (E*_k - E_k) e^-Phi*_k + sum_k E_k (e^-Phi*_k - e^-Phi^_k) + I0 (e^-Phi*_K - e^-Phi^_K),
// and |Phi*_k - Phi^_k| <= D_k = sum_{j<k} delta_j with delta_j >= |dPhi*_j - dPhi^_j|, so
//   |I - I_h| <= sum_k eps_k e^(-Phi^_k + D_k) + sum_k E_k e^-Phi^_k (e^D_k - 1) + I0 e^-Phi^_K (e^D_K - 1),
// eps_k >= |E*_k - E_k|.  The local bounds eps_k, delta_k come from the values of g(f) and tau(f)
// on the segment: Taylor bounds through max |f'| and max |f''| where g and tau are smooth there
// (no transfer-function breakpoint in f's range, no break of the field), the oscillation of g
// and tau where they are not (a jump costs its size times the segment, once).
//
// f's range and derivatives on a segment come from a Chebyshev proxy of f fitted there (exact
// for ramps and trilinear cells; for analytic fields resolved to its tail, whose size widens the
// ranges); derivative bounds are the sums of the proxy's derivative coefficients, which hold for
// the proxy.  The bound is therefore as rigorous as the proxy is close to the field.
#include <string>

#include "lib/discrete_raycast.h"
#include "lib/geometry.h"
#include "lib/scene.h"

namespace vrv {

struct DiscreteErrorBound {
  // Why no bound is derived (empty when one is): an RGB scene, an opacity/colour transfer function,
  // or a strategy with a partial step (why_no_error_bound).
  std::string unavailable;
  double bound = 0;      // |I - I_h| <= bound
  long segments = 0;     // segments of the rule (end gaps of the sample rules included)
  long smooth = 0;       // of which bounded through derivatives (the rest through oscillations)
  long evaluations = 0;  // field evaluations (the proxies and the samples)
  // I_h - I_h(analysed_configuration): what the segment analysis leaves out, cast exactly (0 when
  // the configuration is analysed as it is); the bound is the analysed one's plus |this|.
  double cast_difference = 0;
  bool available() const { return unavailable.empty(); }
};

// The segments of lib/rule_segments.h are those of double-precision raycasts with rules riemann,
// alpha, trapezoid or exact_linear, one sample per step, post-classification, no correction,
// termination, skipping or tables.  For anything else the bound and the estimate analyse the
// nearest such configuration -- the same placement with one sample per step N times shorter for N
// oversamples, exact_linear for moreland (the same nodes), the rest dropped -- and add the exact
// difference of the two raycasts: the opacity correction's mismatch (and the oversamples' offset
// from the finer steps), the tables' quantisation, float's rounding, what termination and skipping
// drop, moreland's average opacity.  Those terms do not shrink with the step, and a model of each
// would approximate what one more raycast gives exactly.
// outside_segment_analysis: empty when `config` is analysed as it is, else what is not.
std::string outside_segment_analysis(const DiscreteConfig& config);
DiscreteConfig analysed_configuration(const DiscreteConfig& config);

// Throws what discrete_raycast throws for an invalid configuration.
DiscreteErrorBound discrete_error_bound(const Scene& scene, const Ray& ray, const DiscreteConfig& config);

// DiscreteErrorBound::unavailable for this scene and configuration, whatever the ray.
std::string why_no_error_bound(const Scene& scene, const DiscreteConfig& config);

// I_h(config) - I_h(base) on one ray, adding both raycasts' samples to `evaluations`.
double cast_difference(const Scene& scene, const Ray& ray, const DiscreteConfig& config, const DiscreteConfig& base,
                       long& evaluations);

// Field evaluations per segment for the bound (an analytic field's 17-node proxy and the sample; a
// field that needs longer proxies takes more): for work estimates.
inline constexpr int kErrorBoundEvaluationsPerSegment = 18;

}  // namespace vrv
