#include "lib/geometry.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace vrv {

Ray make_ray(const Vec3& origin, const Vec3& direction) {
  if (!origin.allFinite()) throw std::invalid_argument("ray origin is not finite");
  if (!direction.allFinite()) throw std::invalid_argument("ray direction is not finite");
  // Scale first so that tiny or huge directions normalise without under- or overflow.
  const double scale = direction.cwiseAbs().maxCoeff();
  if (scale == 0) throw std::invalid_argument("ray direction is zero");
  const Vec3 d = direction / scale;
  return Ray{origin, d / d.norm()};
}

std::optional<Interval> clip(const Ray& ray, const Box& box) {
  double t0 = 0;
  double t1 = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    const double o = ray.origin[a];
    const double d = ray.direction[a];
    if (d == 0) {
      // Parallel to this slab: inside it (faces included) or a miss; no 0 * inf.
      if (o < box.min[a] || o > box.max[a]) return std::nullopt;
      continue;
    }
    double near = (box.min[a] - o) / d;
    double far = (box.max[a] - o) / d;
    if (near > far) std::swap(near, far);
    t0 = std::max(t0, near);
    t1 = std::min(t1, far);
  }
  if (!(t0 <= t1)) return std::nullopt;
  return Interval{t0, t1};
}

}  // namespace vrv
