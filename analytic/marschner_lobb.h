#pragma once
// The Marschner-Lobb (1994) test signal on world coordinates:
//   f(x,y,z) = (1 - sin(pi z / 2) + alpha (1 + rho_r(sqrt(x^2 + y^2)))) / (2 (1 + alpha)),
//   rho_r(r) = cos(2 pi fM cos(pi r / 2)).
#include <limits>
#include <numbers>
#include <vector>

#include "analytic/vec3.h"

namespace vrv {

struct MarschnerLobb {
  double fM = 6;
  double alpha = 0.25;

  double value(const Vec3& p) const;
  int degree_along_ray() const { return -1; }
  // |d/dr of the phase 2 pi fM cos(pi r / 2)| <= pi^2 fM, plus pi/2 from sin(pi z / 2).
  double bandwidth() const {
    constexpr double pi = std::numbers::pi;
    return pi * pi * fM + pi / 2;
  }
  // Smooth everywhere: no breaks on any ray (any ray and interval types).
  void append_breaks(const auto&, const auto&, std::vector<double>&) const {}
  // Absolute rounding of value(): its terms are O(1) whatever f is, so f near 0 carries noise
  // of a few ulps of 1, not of f.  The phase 2 pi fM cos(pi r / 2) is rounded to ~1 ulp of
  // 2 pi fM, which rho_r passes on and alpha / (2 (1 + alpha)) scales; the rest is ~4 ulps.
  double value_noise() const {
    constexpr double eps = std::numeric_limits<double>::epsilon();
    return (4 + 2 * std::numbers::pi * fM * alpha / (1 + alpha)) * eps;
  }
};

}  // namespace vrv
