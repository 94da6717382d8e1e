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
  // The line's direction as given, before normalising (scaled by a power of two, so exact), or
  // zero when `direction` is itself exact: normalising rounds, and carried 1e15 units that
  // rounding moves the ray by 0.1 (clip_in_frame follows the given line instead).
  Vec3 given = Vec3::Zero();
  Vec3 at(double t) const { return origin + t * direction; }
};

// Normalises the direction (keeping it as given in Ray::given); throws std::invalid_argument for
// a zero or non-finite vector.
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

// The ray in its own frame: positions local.origin + s * local.direction for s in iv, with
// local.origin near the box, so that no position loses the digits of a large t (origin + t d
// at t = 1e14 is off by ~1e-2).  Global parameters are t = t_offset + s.
struct RayFrame {
  Ray local;
  Interval iv;                 // inside the box, in the local parameter s
  double t_offset = 0;         // global t of the local origin (rounded)
  double position_error = 0;   // bound on the distance of local.origin from the exact ray line
                               // beyond the rounding every position has anyway (0 near the box)
  double t_entry() const { return t_offset + iv.t0; }
  double t_exit() const { return t_offset + iv.t1; }
};

// clip() in the ray's frame.  An origin within kNearOrigin half-diagonals of the box centre is
// its own frame (exactly clip()); a farther one is carried along the line as given (Ray::given)
// to the box entry point in double-double arithmetic (error-free products and sums), rounded
// once, and clipped again
// there: the entry point is then off the line by its own rounding (charged through
// position_error) and the clip is as robust as for a ray starting next to the box.
inline constexpr double kNearOrigin = 8;
std::optional<RayFrame> clip_in_frame(const Ray& ray, const Box& box);

}  // namespace vrv
