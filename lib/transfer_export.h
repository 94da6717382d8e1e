#pragma once
// The transfer function written for other renderers: a table of the scalar value against
// emission and extinction (vrv's convention, per unit world length) and against opacity and
// colour (the renderers' convention: opacity per unit distance L and colour, so that a sample
// standing for a distance H gets alpha = 1 - (1 - opacity)^(H / L) and emits colour * alpha).
//
// The conventions meet through tau = -ln(1 - opacity) / L and g = colour * tau, i.e.
// opacity = 1 - exp(-tau L), colour = g / tau; where tau = 0 the colour is its limit within the
// segment (emission and extinction vanishing together), 0 only where the scene emits without
// absorbing or neither does anywhere near.
#include <array>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "lib/scene.h"
#include "lib/transfer_function.h"

namespace vrv {

struct TransferRow {
  double value = 0, emission = 0, extinction = 0, opacity = 0, color = 0;
};

// Rows at every breakpoint (a jump gives two rows with the same value: the left limit, then
// the right one) and at `per_segment` - 1 equally spaced values inside every segment between
// breakpoints; beyond the first and last rows the function is constant (as renderers clamp).
// Opacity is per unit distance `unit_distance` (> 0, else std::invalid_argument).
std::vector<TransferRow> tabulate_transfer(const TransferFunction& tf, double unit_distance, int per_segment);

// CSV: "value,emission,extinction,opacity,color" then one line per row, 17 significant digits.
std::string transfer_csv(const std::vector<TransferRow>& rows);

// The renderer's convention as JSON:
//   {"unit_distance": L, "opacity": [[v, a], ...], "color": [[v, c], ...], "exact": bool,
//    "scalar_range": [lo, hi], "alpha_at_sample_distance": "1 - (1 - opacity)^(H / unit_distance)", ...}
// For an opacity/colour scene the control points are the scene's own, and L its unit_length
// (`unit_distance` is ignored): exact.  For an emission/extinction scene, opacity and colour are
// not piecewise linear in the value, so they are the tabulated rows (exact at the rows, linear
// interpolation between them is the approximation: "exact": false, with the largest opacity
// and colour gap measured at the midpoints of the rows as "max_interpolation_error").
// "emission_without_extinction": true when g > 0 where tau = 0 somewhere (inexpressible as
// opacity and colour).
nlohmann::ordered_json transfer_json(const TransferFunction& tf, double unit_distance, int per_segment);

// An RGB scene's channels tabulated at the same values (the union of their breakpoints; a row
// where any channel changes), so that row i is one value in all three tables; the extinction,
// hence the opacity, is every channel's.
std::array<std::vector<TransferRow>, 3> tabulate_color_transfer(const ColorChannels& color, double unit_distance,
                                                                int per_segment);
// CSV: "value,emission_r,emission_g,emission_b,extinction,opacity,color_r,color_g,color_b".
std::string color_transfer_csv(const std::array<std::vector<TransferRow>, 3>& rows);
// As transfer_json with "channels": ["R", "G", "B"] and colour points [v, r, g, b]: an RGB
// opacity/colour scene's own points (exact) when the channels' points share their values, else
// the joint table's rows (not exact; the gaps are the largest over the channels).
nlohmann::ordered_json color_transfer_json(const ColorChannels& color, double unit_distance, int per_segment);

}  // namespace vrv
