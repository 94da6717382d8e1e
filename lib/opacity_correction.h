#pragma once
// Opacity corrections for oversampled raycasting in the renderer's convention (opacity per
// unit step, colour; an oversampling factor N divides the unit step into N samples):
// Lacroute / Lichtenbelt, Schulze, and Lee & Newman (exact and the quadratic fit).
// See docs/opacity-correction.md and ../shared/papers/000_* (Lee & Newman, WSCG 2007).
//
// Inputs are opacities in [0, 1]; anything outside is clamped into [0, 1] and NaN is read as 0,
// so every output opacity is finite and in [0, 1].
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace vrv {

enum class Correction { none, lacroute, schulze, lee_newman, lee_newman_quadratic };

// "none", "lacroute", "schulze", "lee_newman", "lee_newman_quadratic"; nullopt otherwise.
std::optional<Correction> parse_correction(std::string_view name);
std::string correction_list();  // its names in order, "a, b, c": the choices an error offers
std::string_view correction_name(Correction c);

// Lacroute / Lichtenbelt (eq. 5): alpha' = 1 - (1 - alpha)^(1/N), as -expm1(log1p(-alpha) / N).
// alpha = 0 -> 0, alpha = 1 -> 1, N = 1 -> alpha exactly.  Throws std::invalid_argument if N < 1.
double lacroute(double alpha, int N);

// Schulze's colour factor (eq. 6): alpha' / alpha with alpha' = lacroute(alpha, N), computed as
// -expm1(x / N) / -expm1(x), x = log1p(-alpha), without 0/0: alpha = 0 -> 1/N (the limit),
// alpha = 1 -> 1.  Throws std::invalid_argument if N < 1.
double schulze_color_scale(double alpha, int N);

// Lee & Newman (eqs. 9-12): the p in [0, 1] with prod_k (1 - p alphas[k]) = 1 - alpha_unit, where
// alphas are the N oversamples of one group (one voxel) and alpha_unit is the unit sample's
// opacity (the paper's alpha_u1, which equals alphas[0]: the first oversample sits on the unit
// sample).  Solved in log space, F(p) = sum log1p(-p alphas[k]) - log1p(-alpha_unit) (decreasing,
// concave), by TOMS 748 on [0, 1] to within ~2 ulps of the root; never through eq. 11's polynomial.
// Conventions: p = 1 when the group is empty or all zero (any p solves it); p = 0 when
// alpha_unit = 0 (and some alpha > 0); p = 1 when even p = 1 leaves the group more transparent
// than the target (no root in [0, 1]: only when alpha_unit > 1 - prod(1 - alphas[k]), which
// cannot happen for alpha_unit = alphas[0]), in particular for alpha_unit = 1.
double lee_newman_p(std::span<const double> alphas, double alpha_unit);

// The paper's quadratic fit (eqs. 13-16): F^(p) = A p^2 + B p + C through F at p = 0, 1/2, 1,
// with F(p) = prod_k (1 - p alphas[k]) - (1 - alpha_unit) (eq. 11 up to its sign (-1)^N, evaluated
// as a product), (A, B, C) = M^-1 (F(0), F(1/2), F(1)) with M^-1 computed once (Eigen), and the
// root in [0, 1] from the cancellation-free quadratic formula (linear when A = 0, double root when
// the discriminant rounds negative).  The same edge conventions as lee_newman_p.
double lee_newman_quadratic_p(std::span<const double> alphas, double alpha_unit);

// Corrects one group in place (alphas and colors; colors may be empty, else the same size):
//   none                  leaves both;
//   lacroute              alpha <- lacroute(alpha, N) per sample, colours unchanged;
//   schulze               as lacroute, and colour <- colour * schulze_color_scale(alpha, N);
//   lee_newman(_quadratic) alpha <- p alpha with p from the group (aiming at alpha_unit, the unit
//                         sample's opacity: alphas[0] unless given), colours unchanged.
// A Lee & Newman group is the m <= N consecutive oversamples of one unit step, by default the
// first on the unit sample (give alpha_unit when none of them is, e.g. centred oversamples); a
// partial group (m < N, the end of a ray) aims at the transparency (1 - alpha_unit)^(m/N), which
// is the full-group target for m = N.  Throws std::invalid_argument if N < 1, colors has a
// different non-zero size, or a Lee & Newman group has more than N samples.
void correct_group(Correction c, std::span<double> alphas, std::span<double> colors, int N,
                   std::optional<double> alpha_unit = std::nullopt);

}  // namespace vrv
