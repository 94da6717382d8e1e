#pragma once
// The visibility study (Gao, Huang, Shen, Kohl, "Visibility culling using plenoptic opacity
// functions for large volume visualization", IEEE Vis 2003): the opacity identities behind
// POFs, early ray termination, and block culling (studies/visibility/culling.h).
#include <span>

#include "lib/transfer_function.h"

namespace vrv {

// alpha' = 1 - (1 - alpha)^k, the opacity of a ray whose extinction is scaled by k, in the
// stable form -expm1(k log1p(-alpha)).
double scaled_opacity(double alpha, double k);
// Eq. (3): 1 - prod (1 - alpha_i)^{k_i}, the opacity under the sum of the scaled bases.
double combined_opacity(std::span<const double> alphas, std::span<const double> ks);
// Eq. (3) from optical depths Phi_i = -log(1 - alpha_i): -expm1(-sum k_i Phi_i).  Carrying the
// transparency in log space keeps it where alpha is near 1; from alpha, 1 - alpha has lost the
// digits of a small transparency T (relative error ~1e-16 / T, raised to the power k).
double combined_opacity_of_depths(std::span<const double> depths, std::span<const double> ks);
// The (real) number of samples of constant opacity alpha until the accumulated opacity reaches
// `threshold`: log(1 - threshold) / log(1 - alpha) (the paper's 58.4 for 0.95 and 0.05).
double samples_to_threshold(double alpha, double threshold);

// The most any stretch of a ray can add for the alpha rule: every sample adds at most its colour
// times its opacity, so a remainder adds at most max colour (g / tau, or the colour curve)
// times its opacity, plus the background times its transparency: max(max colour, background).
// Colour g / tau of an affine branch is monotone, so its extremes sit at the control values and
// at the ends; infinite when some value has tau = 0 and g > 0.
double max_colour(const TransferFunction& tf);
double max_radiance(const TransferFunction& tf, double background);

// The extinction curve times k (emission/extinction transfer functions only), with no emission:
// a ray's value is then the background times its transparency.
TransferFunction absorption_only(const PiecewiseLinear& extinction, double k);
PiecewiseLinear scaled(const PiecewiseLinear& curve, double k);
PiecewiseLinear sum(const PiecewiseLinear& a, const PiecewiseLinear& b);

}  // namespace vrv
