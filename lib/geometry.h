#pragma once
// Points, boxes and rays in world space, and clipping a ray to a closed box.
#include <optional>

#include "analytic/vec3.h"

namespace vrv {

// Closed axis-aligned box [min, max].
struct Box {
  Vec3 min{-1, -1, -1};
  Vec3 max{1, 1, 1};
  Vec3 extent() const { return max - min; }
};

// origin + t * direction with |direction| = 1, so t is world length.
struct Ray {
  Vec3 origin;
  Vec3 direction;
  Vec3 at(double t) const { return origin + t * direction; }
};

// Normalises the direction; throws std::invalid_argument for a zero or non-finite vector.
Ray make_ray(const Vec3& origin, const Vec3& direction);

// Parameter interval [t0, t1] along a ray, t0 <= t1.
struct Interval {
  double t0 = 0;
  double t1 = 0;
  double length() const { return t1 - t0; }
};

// The part of the ray with t >= 0 inside the closed box, or nothing when the ray misses.
// A ray that starts inside begins at t = 0; rays along faces and edges count as inside.
std::optional<Interval> clip(const Ray& ray, const Box& box);

}  // namespace vrv
