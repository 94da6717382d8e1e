#include "analytic/marschner_lobb.h"

#include <algorithm>
#include <cmath>

namespace vrv {
namespace {

using std::numbers::pi;

// max |sin(pi u / 2)| for u in [lo, hi]: 1 where an odd integer lies inside, else at an end
// (between a peak at an odd u and a zero at an even u it is monotone).
double max_abs_sin_half_pi(double lo, double hi) {
  if (!(hi - lo < 2)) return 1;  // also NaN
  if (2 * std::ceil((lo - 1) / 2) + 1 <= hi) return 1;
  return std::max(std::abs(std::sin(pi * lo / 2)), std::abs(std::sin(pi * hi / 2)));
}

// Widens a computed coordinate range by far more than its rounding (positions are a few ulps
// off): only the bound's monotone factors see it.
constexpr double kSlack = 1e-9;

}  // namespace

double MarschnerLobb::value(const Vec3& p) const {
  const double r = std::hypot(p.x(), p.y());
  const double rho_r = std::cos(2 * pi * fM * std::cos(pi * r / 2));
  return (1 - std::sin(pi * p.z() / 2) + alpha * (1 + rho_r)) / (2 * (1 + alpha));
}

Vec3 MarschnerLobb::piece_gradient(const Vec3& p, const Vec3&) const {
  // d rho_r / dr = A (pi/2) sin(A cos(pi r / 2)) sin(pi r / 2), A = 2 pi fM, and d r / dx = x / r:
  // sin(pi r / 2) / r = (pi/2) sinc(pi r / 2) keeps the axis (r = 0) exact.
  const double r = std::hypot(p.x(), p.y());
  const double a = 2 * pi * fM;
  const double w = pi * r / 2;
  const double sinc = w < 1e-4 ? 1 - w * w / 6 : std::sin(w) / w;
  const double k = 1 / (2 * (1 + alpha));
  const double radial = alpha * a * (pi / 2) * std::sin(a * std::cos(w)) * (pi / 2) * sinc * k;
  return {radial * p.x(), radial * p.y(), -(pi / 2) * std::cos(pi * p.z() / 2) * k};
}

double MarschnerLobb::bandwidth_between(const Vec3& p, const Vec3& q) const {
  const Vec3 d = q - p;
  const double length = d.norm();
  if (!(length > 0)) return bandwidth();
  const Vec3 u = d / length;
  // Radial term 2 pi fM cos(pi r / 2): d/dt = -pi^2 fM sin(pi r / 2) dr/dt.  In the xy plane
  // r(t) = sqrt(r0^2 + w^2 (t - t*)^2) with w = |u_xy|, so |dr/dt| = w^2 |t - t*| / r grows
  // away from the closest approach t* and is largest at an end: |p_xy . u_xy| / |p_xy|.
  const double w = std::hypot(u.x(), u.y());
  const auto radial_speed = [&](const Vec3& e) {
    const double r = std::hypot(e.x(), e.y());
    return r > 0 ? std::min(w, std::abs(e.x() * u.x() + e.y() * u.y()) / r) : w;
  };
  const double r_p = std::hypot(p.x(), p.y()), r_q = std::hypot(q.x(), q.y());
  double r_min = std::min(r_p, r_q);
  if (w > 0) {
    // The closest approach to the axis, if it lies on the segment.
    const double s = -(p.x() * d.x() + p.y() * d.y()) / (d.x() * d.x() + d.y() * d.y());
    if (s > 0 && s < 1) r_min = std::hypot(p.x() + s * d.x(), p.y() + s * d.y());
  }
  const double r_max = std::max(r_p, r_q);
  const double radial = pi * pi * std::abs(fM) * std::max(radial_speed(p), radial_speed(q)) *
                        max_abs_sin_half_pi(r_min - kSlack * (1 + r_min), r_max + kSlack * (1 + r_max));
  // z term sin(pi z / 2): d/dt = (pi / 2) cos(pi z / 2) u_z, |cos(pi z / 2)| = |sin(pi (z + 1) / 2)|.
  const double z_lo = std::min(p.z(), q.z()), z_hi = std::max(p.z(), q.z());
  const double axial = pi / 2 * std::abs(u.z()) *
                       max_abs_sin_half_pi(z_lo + 1 - kSlack * (1 + std::abs(z_lo)),
                                           z_hi + 1 + kSlack * (1 + std::abs(z_hi)));
  const double omega = radial + axial;
  return omega <= bandwidth() ? omega : bandwidth();  // NaN (huge coordinates): the global bound
}

}  // namespace vrv
