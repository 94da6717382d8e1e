#pragma once
// The Marschner-Lobb (1994) test signal on world coordinates:
//   f(x,y,z) = (1 - sin(pi z / 2) + alpha (1 + rho_r(sqrt(x^2 + y^2)))) / (2 (1 + alpha)),
//   rho_r(r) = cos(2 pi fM cos(pi r / 2)).
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <string_view>
#include <vector>

#include "analytic/vec3.h"

namespace vrv {

struct MarschnerLobb {
  double fM = 6;
  double alpha = 0.25;
  // The scene file's [field] kind, and the numbers that define the field (its scene hash covers them).
  static constexpr std::string_view kind = "marschner_lobb";
  std::array<double, 2> parameters() const { return {fM, alpha}; }

  double value(const Vec3& p) const;
  // grad f at p (smooth everywhere: `inside`, the point naming a smooth piece, is not needed).
  Vec3 piece_gradient(const Vec3& p, const Vec3& inside) const;
  // Absolute rounding of piece_gradient's components at p: the radial phase A cos(pi r / 2),
  // A = 2 pi fM, is off by a few ulps of A (hypot's, cos's and the product's rounding), which sin passes
  // on and the radial components' factor alpha A (pi/2)^2 sinc / (2 (1 + alpha)) x (x or y)
  // multiplies (so it vanishes on the axis, where the radial components are exactly 0); the
  // factor's own rounding and the z term are a few ulps of the terms.
  double gradient_noise(const Vec3& p) const {
    constexpr double pi = std::numbers::pi;
    constexpr double eps = std::numeric_limits<double>::epsilon();
    const double a = 2 * pi * std::abs(fM);
    const double radial = std::abs(alpha) * pi * pi / 4 * a * (1 + a) * std::max(std::abs(p.x()), std::abs(p.y()));
    return 6 * eps * (pi / 2 + radial) / (2 * std::abs(1 + alpha));
  }
  int degree_along_ray() const { return -1; }
  // |d/dr of the phase 2 pi fM cos(pi r / 2)| <= pi^2 fM, plus pi/2 from sin(pi z / 2).
  double bandwidth() const {
    constexpr double pi = std::numbers::pi;
    return pi * pi * fM + pi / 2;
  }
  // The same bound on the segment from p to q only (sizes first panels locally): the radial
  // term's frequency pi^2 fM |sin(pi r / 2)| |dr/dt| vanishes near the axis and wherever the
  // line runs along it, the z term's (pi/2) |cos(pi z / 2)| |dz/dt| where z is odd.
  double bandwidth_between(const Vec3& p, const Vec3& q) const;
  // Smooth everywhere: no breaks on any ray (any ray and interval types).
  void append_breaks(const auto&, const auto&, std::vector<double>&) const {}
  // |grad f| <= (pi/2 + alpha pi^2 fM) / (2 (1 + alpha)): the z term and the radial term.
  double max_change_within(double distance) const {
    constexpr double pi = std::numbers::pi;
    return distance * (pi / 2 + std::abs(alpha) * pi * pi * std::abs(fM)) / (2 * std::abs(1 + alpha));
  }
  // Absolute rounding of value(): its terms are O(1) whatever f is, so f near 0 carries noise
  // of a few ulps of 1, not of f.  The phase 2 pi fM cos(pi r / 2) is rounded to ~1 ulp of
  // 2 pi fM, which rho_r passes on and alpha / (2 (1 + alpha)) scales; the rest is ~4 ulps.
  double value_noise() const {
    constexpr double eps = std::numeric_limits<double>::epsilon();
    return (4 + 2 * std::numbers::pi * fM * alpha / (1 + alpha)) * eps;
  }
  // Where |coordinates| reach `extent` beyond 16 (lib/field.h, kUnitCoordinates), their own
  // rounding (a few ulps each) moves the z term by its slope and the radial term by its own, which
  // only x and y feed: a long ray along the axis is not charged the radial term's fM.
  double value_noise_within(const Vec3& extent) const {
    constexpr double pi = std::numbers::pi;
    constexpr double eps = std::numeric_limits<double>::epsilon();
    if (!(extent.maxCoeff() > 16)) return value_noise();
    const double scale = 4 * eps / (2 * std::abs(1 + alpha));
    const double moved = scale * (pi / 2 * extent.z() + std::abs(alpha) * pi * pi * std::abs(fM) * std::hypot(extent.x(), extent.y()));
    return std::isfinite(moved) ? value_noise() + moved : value_noise();
  }
};

}  // namespace vrv
