#pragma once
// What an integrator needs from a scalar field.  Fields are plain types used through
// templates (no virtual call per evaluation); a scene holds one of them in a std::variant.
#include <cmath>
#include <concepts>
#include <limits>
#include <vector>

#include "lib/geometry.h"

namespace vrv {

template <class F>
concept ScalarField = requires(const F& f, const Vec3& p, const Ray& ray, Interval iv,
                               std::vector<double>& breaks) {
  // f at a world position.
  { f.value(p) } -> std::convertible_to<double>;
  // Degree of the polynomial t -> f(ray.at(t)) between structural breaks, or -1 when the
  // field is smooth but not a polynomial (then it is resolved adaptively).
  { f.degree_along_ray() } -> std::convertible_to<int>;
  // An upper bound on the angular frequency of f along any line (radians per unit length),
  // or 0 when unknown; it only sizes the first panels, correctness never depends on it.
  { f.bandwidth() } -> std::convertible_to<double>;
  // Appends the parameters in (iv.t0, iv.t1) where f is not smooth (grid cell faces).
  f.append_breaks(ray, iv, breaks);
};

// The absolute rounding level of f's values where the field states one (value_noise()), else 0
// (values then count as accurate to a few ulps of themselves).  Without it, a panel where f is
// near 0 but computed from O(1) terms never looks resolved, and the integrator splits it to its
// work cap.
template <class F>
double field_value_noise(const F& f) {
  if constexpr (requires { { f.value_noise() } -> std::convertible_to<double>; })
    return f.value_noise();
  else
    return 0;
}

// A bound on f's angular frequency along the segment from p to q (radians per unit length)
// where the field states one (bandwidth_between()), else its global bandwidth().  Like
// bandwidth() it only sizes first panels: Marschner-Lobb's radial term is slow near its axis.
template <class F>
double field_bandwidth_between(const F& f, const Vec3& p, const Vec3& q) {
  if constexpr (requires { { f.bandwidth_between(p, q) } -> std::convertible_to<double>; })
    return f.bandwidth_between(p, q);
  else
    return f.bandwidth();
}

// Coordinates up to this size are what value_noise() is stated for.
inline constexpr double kUnitCoordinates = 16;

// The largest change of f between two points `distance` apart where the field states one
// (max_change_within()), else infinity; 0 for distance 0.  It charges the rounding of a far
// ray's entry point (RayFrame::position_error) to the estimate.
template <class F>
double field_change_within(const F& f, double distance) {
  if (!(distance > 0)) return 0;
  if constexpr (requires { { f.max_change_within(distance) } -> std::convertible_to<double>; })
    return f.max_change_within(distance);
  else
    return std::numeric_limits<double>::infinity();
}

// The rounding level of f's values on a stretch whose coordinates reach `extent` in size (per
// axis, the largest |coordinate|): field_value_noise() where coordinates are of order one; beyond
// kUnitCoordinates the rounding of the coordinates themselves (a few ulps of extent) moves f by
// up to field_change_within of that (Marschner-Lobb at |x| ~ 1e5 is noisy at ~1e-10, and no panel
// resolves below it).  A field that knows better states it for the extent itself
// (value_noise_within()): a linear ramp's rounding is relative to its own terms, Marschner-Lobb's
// radial term feels only the rounding of x and y.
template <class F>
double field_value_noise(const F& f, const Vec3& extent) {
  if constexpr (requires { { f.value_noise_within(extent) } -> std::convertible_to<double>; }) {
    return f.value_noise_within(extent);
  } else {
    const double noise = field_value_noise(f);
    const double size = extent.maxCoeff();
    if (!(size > kUnitCoordinates)) return noise;
    const double moved = field_change_within(f, 4 * std::numeric_limits<double>::epsilon() * size);
    return std::isfinite(moved) ? noise + moved : noise;
  }
}

}  // namespace vrv
