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
  // Why no bound is derived for this configuration (empty when one is): the bound covers plain
  // double-precision raycasts (rules riemann, alpha, trapezoid, exact_linear; one sample per
  // step; no correction, termination, skipping, tables or pre-classification; an
  // emission/extinction transfer function; a strategy without a partial step).
  std::string unavailable;
  double bound = 0;      // |I - I_h| <= bound
  long segments = 0;     // segments of the rule (end gaps of the sample rules included)
  long smooth = 0;       // of which bounded through derivatives (the rest through oscillations)
  long evaluations = 0;  // field evaluations (the proxies and the samples)
  bool available() const { return unavailable.empty(); }
};

// Throws what discrete_raycast throws for an invalid configuration.
DiscreteErrorBound discrete_error_bound(const Scene& scene, const Ray& ray, const DiscreteConfig& config);

// DiscreteErrorBound::unavailable for this scene and configuration, whatever the ray.
std::string why_no_error_bound(const Scene& scene, const DiscreteConfig& config);

// Field evaluations per segment for the bound (an analytic field's 17-node proxy and the sample; a
// field that needs longer proxies takes more): for work estimates.
inline constexpr int kErrorBoundEvaluationsPerSegment = 18;

}  // namespace vrv
