#include "lib/camera.h"

#include "lib/camera_frame.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

#include <Eigen/Geometry>
#include <fmt/format.h>

namespace vrv {
namespace {

constexpr double kDegree = std::numbers::pi / 180;

[[noreturn]] void bad(std::string_view field, const std::string& reason) {
  throw CameraError(std::string(field), reason);
}

void check_finite(const Vec3& v, std::string_view field) {
  if (!v.allFinite()) bad(field, fmt::format("not finite: [{}, {}, {}]", v[0], v[1], v[2]));
}

void check_finite(double x, std::string_view field) {
  if (!std::isfinite(x)) bad(field, fmt::format("not finite: {}", x));
}

// Pixel centre in [-1, 1]^2, x to the right, y up (row 0 is the top).
double ndc_x(const Camera& c, double px) { return 2 * px / c.width - 1; }
double ndc_y(const Camera& c, double py) { return 1 - 2 * py / c.height; }

}  // namespace

CameraError::CameraError(std::string field, std::string reason)
    : std::invalid_argument(fmt::format("camera.{}: {}", field, reason)),
      field_(std::move(field)),
      reason_(std::move(reason)) {}

static_assert(names_complete(kProjectionNames));

std::string_view to_string(Projection p) { return name_of(kProjectionNames, p); }

CameraFrame camera_frame(const Camera& c) {
  const Vec3 forward = (c.target - c.eye).normalized();
  const Vec3 right = forward.cross(c.up).normalized();
  return {forward, right, right.cross(forward)};
}

Ray Camera::ray(int x, int y) const { return ray_at(x + 0.5, y + 0.5); }

Ray Camera::ray_at(double px, double py) const {
  if (projection == Projection::fan) {
    const double theta =
        (angle_degrees - fov_degrees / 2 + fov_degrees * px / width) * kDegree;
    return make_ray(eye, Vec3(std::cos(theta), std::sin(theta), 0));
  }
  const CameraFrame f = camera_frame(*this);
  const double aspect = static_cast<double>(width) / height;
  const double u = ndc_x(*this, px), v = ndc_y(*this, py);
  if (projection == Projection::orthographic) {
    const double half_h = extent / 2, half_w = half_h * aspect;
    return make_ray(eye + u * half_w * f.right + v * half_h * f.up, f.forward);
  }
  const double half_h = std::tan(fov_degrees * kDegree / 2), half_w = half_h * aspect;
  return make_ray(eye, f.forward + u * half_w * f.right + v * half_h * f.up);
}

void validate(const Camera& c) {
  for (auto [side, name] : {std::pair{c.width, "width"}, std::pair{c.height, "height"}})
    if (side < 1 || side > kMaxImageSide)
      bad(name, fmt::format("must be in [1, {}], got {}", kMaxImageSide, side));
  check_finite(c.eye, "eye");
  check_finite(c.fov_degrees, "fov");
  if (c.projection == Projection::fan) {
    check_finite(c.angle_degrees, "angle");
    if (c.height != 1) bad("height", fmt::format("a fan is one row of rays: height must be 1, got {}", c.height));
    if (!(c.fov_degrees > 0 && c.fov_degrees <= 360))
      bad("fov", fmt::format("a fan's angle must be in (0, 360] degrees, got {}", c.fov_degrees));
    return;
  }
  check_finite(c.target, "target");
  check_finite(c.up, "up");
  const Vec3 view = c.target - c.eye;
  if (!(view.norm() > 0)) bad("target", "equals the eye (no view direction)");
  if (!view.allFinite()) bad("target", "too far from the eye (the view direction overflows)");
  // sin of the angle between up and the view direction; tiny means no usable frame.
  if (!(c.up.norm() > 0) || !(view.normalized().cross(c.up.normalized()).norm() > 1e-9))
    bad("up", fmt::format("must not be zero or parallel to the view direction, got [{}, {}, {}]",
                          c.up[0], c.up[1], c.up[2]));
  if (c.projection == Projection::perspective) {
    if (!(c.fov_degrees > 0 && c.fov_degrees < 180))
      bad("fov", fmt::format("must be in (0, 180) degrees, got {}", c.fov_degrees));
  } else {
    check_finite(c.extent, "extent");
    if (!(c.extent > 0)) bad("extent", fmt::format("must be positive, got {}", c.extent));
  }
}

Camera default_camera(const Box& box) {
  Camera c;
  const Vec3 centre = 0.5 * (box.min + box.max);
  c.target = centre;
  c.eye = centre - Vec3(0, 0, 2.5 * box.extent().norm());
  return c;
}

}  // namespace vrv
