#pragma once
// f(x) = offset + dot(gradient, x): linear along every ray, so with a piecewise-linear
// transfer function every piece of a ray has a closed form.
#include <array>
#include <cmath>
#include <limits>
#include <string_view>
#include <vector>

#include "analytic/vec3.h"

namespace vrv {

struct LinearRamp {
  Vec3 gradient{1, 0, 0};
  double offset = 0;
  // The scene file's [field] kind, and the numbers that define the field (its scene hash covers them).
  static constexpr std::string_view kind = "linear_ramp";
  std::array<double, 4> parameters() const { return {gradient[0], gradient[1], gradient[2], offset}; }

  double value(const Vec3& p) const { return offset + gradient.dot(p); }
  int degree_along_ray() const { return 1; }
  Vec3 piece_gradient(const Vec3&, const Vec3&) const { return gradient; }
  double gradient_noise(const Vec3&) const { return 0; }
  double bandwidth() const { return 0; }
  // Smooth everywhere: no breaks on any ray (any ray and interval types).
  void append_breaks(const auto&, const auto&, std::vector<double>&) const {}
  double max_change_within(double distance) const { return distance * gradient.norm(); }
  // Absolute rounding of value() where |coordinates| reach `extent`: a few ulps of its terms, so
  // relative to the ramp's own scale (a gradient of 1e-13 is exact to ~1e-29, not to ulps of 1).
  double value_noise_within(const Vec3& extent) const {
    return 4 * std::numeric_limits<double>::epsilon() * (std::abs(offset) + gradient.cwiseAbs().dot(extent));
  }
};

}  // namespace vrv
