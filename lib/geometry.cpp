#include "lib/geometry.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "lib/util/error_free.h"

namespace vrv {

Ray make_ray(const Vec3& origin, const Vec3& direction) {
  if (!origin.allFinite()) throw std::invalid_argument("ray origin is not finite");
  if (!direction.allFinite()) throw std::invalid_argument("ray direction is not finite");
  // Scale first so that tiny or huge directions normalise without under- or overflow.
  const double scale = direction.cwiseAbs().maxCoeff();
  if (scale == 0) throw std::invalid_argument("ray direction is zero");
  const Vec3 d = direction / scale;
  // Scaled by a power of two near the largest component: exact, and safe to square.
  const int shift = -std::ilogb(scale);
  const Vec3 given = direction.unaryExpr([shift](double c) { return std::scalbn(c, shift); });
  return Ray{origin, d / d.norm(), given};
}

namespace {

// The part of the line with t >= t_min inside the closed box (slab test).
std::optional<Interval> clip_from(const Ray& ray, const Box& box, double t_min) {
  double t0 = t_min;
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

// A point as an unevaluated sum hi + lo per coordinate, |lo| <= ulp(hi) / 2.
struct PointDD {
  Vec3 hi;
  Vec3 lo = Vec3::Zero();
  double error = 0;  // bound on |exact - (hi + lo)| per coordinate

  // += t d: the product and the sum are exact, only the low parts are rounded (twice).
  void advance(const Vec3& d, double t) {
    constexpr double eps = std::numeric_limits<double>::epsilon();
    double bound = 0;
    for (int a = 0; a < 3; ++a) {
      const double q = t * d[a];
      const double q_err = std::fma(t, d[a], -q);
      double s, s_err;
      two_sum(hi[a], q, s, s_err);
      const double low = lo[a] + (s_err + q_err);
      bound = std::max(bound, eps * (std::abs(lo[a]) + 2 * (std::abs(s_err) + std::abs(q_err))));
      two_sum(s, low, hi[a], lo[a]);
    }
    error += bound;
  }
};

}  // namespace

std::optional<Interval> clip(const Ray& ray, const Box& box) { return clip_from(ray, box, 0); }

std::optional<RayFrame> clip_in_frame(const Ray& ray, const Box& box) {
  const Vec3 centre = 0.5 * box.min + 0.5 * box.max;
  const double reach = std::sqrt(3.0) * (0.5 * box.max - 0.5 * box.min).cwiseAbs().maxCoeff();
  const Vec3& d = ray.direction;
  if (!((ray.origin - centre).cwiseAbs().maxCoeff() > kNearOrigin * reach)) {
    const auto iv = clip(ray, box);
    if (!iv) return std::nullopt;
    return RayFrame{ray, *iv, 0, 0};
  }
  // Steps go along the line as given (g), never along the rounded unit d: only the point reached
  // is rounded, and that is charged below.  A step of u along g is u |g| of world length (that
  // product's rounding only relabels t).
  const Vec3& g = ray.given.isZero() ? d : ray.given;
  const double g_norm = g.norm();
  // Walk to the point of closest approach to the centre; each step leaves ~eps of the last.
  PointDD p{ray.origin};
  double t = 0;
  for (int step = 0; step < 4; ++step) {
    const double u = (centre - p.hi).dot(g) / (g_norm * g_norm);
    p.advance(g, u);
    t += u * g_norm;
    if (std::abs(u * g_norm) <= reach) break;
  }
  // Clip there (t >= 0 is s >= -t), move to the entry point, and clip again from it.
  const auto around = clip_from(Ray{p.hi, d}, box, -t);
  if (!around) return std::nullopt;
  p.advance(g, around->t0 / g_norm);
  t += around->t0;
  const auto iv = clip_from(Ray{p.hi, d}, box, -t);
  if (!iv) return std::nullopt;
  // The rounded entry point is off the exact point by lo (known) plus the accumulated error;
  // only the part across the line moves the ray (along it, it only relabels s).
  const Vec3 across = p.lo - p.lo.dot(d) * d;
  return RayFrame{Ray{p.hi, d}, *iv, t, across.norm() + std::sqrt(3.0) * p.error};
}

}  // namespace vrv
