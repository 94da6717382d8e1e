#include "lib/camera.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace vrv {
namespace {

constexpr double kDeg = std::numbers::pi / 180;

double angle_between(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

TEST(Camera, PerspectiveCentralRayPointsAtTarget) {
  Camera c;
  c.eye = Vec3(1, 2, -5);
  c.target = Vec3(0.5, -0.25, 1);
  c.width = 5;  // odd sizes: pixel (2, 1) is the centre
  c.height = 3;
  validate(c);
  const Ray r = c.ray(2, 1);
  EXPECT_EQ(r.origin, c.eye);
  EXPECT_NEAR(angle_between(r.direction, c.target - c.eye), 0, 1e-15);
  EXPECT_NEAR(r.direction.norm(), 1, 1e-15);
}

TEST(Camera, PerspectiveFieldOfViewAndOrientation) {
  Camera c;  // eye (0, 0, -4) looking along +z, up +y
  c.width = 4;
  c.height = 2;
  c.fov_degrees = 60;
  validate(c);
  // Pixel centres at y = +-1/2 of the half height: tan(angle) = tan(30 deg) / 2.
  const Ray top = c.ray(0, 0), bottom = c.ray(0, 1);
  EXPECT_GT(top.direction.y(), 0);  // row 0 is the top: y up
  EXPECT_LT(bottom.direction.y(), 0);
  EXPECT_NEAR(top.direction.y() / top.direction.z(), std::tan(30 * kDeg) / 2, 1e-15);
  // Right-handed: looking along +z with +y up, +x is on the left (column 0).
  EXPECT_GT(c.ray(0, 0).direction.x(), 0);
  EXPECT_LT(c.ray(3, 0).direction.x(), 0);
  // Square pixels: horizontal half-angle scales with the aspect ratio.
  EXPECT_NEAR(-c.ray(3, 0).direction.x() / c.ray(3, 0).direction.z(),
              std::tan(30 * kDeg) * 2 * 0.75, 1e-15);
}

TEST(Camera, OrthographicRaysAreParallelAndSpanExtent) {
  Camera c;
  c.projection = Projection::orthographic;
  c.eye = Vec3(0, 0, -4);
  c.extent = 3;
  c.width = 6;
  c.height = 4;
  validate(c);
  const Vec3 d = c.ray(0, 0).direction;
  EXPECT_NEAR((d - Vec3(0, 0, 1)).norm(), 0, 1e-15);
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      const Ray r = c.ray(x, y);
      EXPECT_NEAR((r.direction - d).norm(), 0, 1e-15);
      EXPECT_NEAR(r.origin.z(), -4, 1e-15);  // origins on the image plane through the eye
    }
  // Pixel centres: the outer rows are half a pixel (extent / height / 2) inside the extent.
  const double pixel = c.extent / c.height;
  EXPECT_NEAR(c.ray(0, 0).origin.y() - c.ray(0, 3).origin.y(), c.extent - pixel, 1e-14);
  EXPECT_NEAR(c.ray(0, 0).origin.y(), c.extent / 2 - pixel / 2, 1e-15);
  EXPECT_NEAR(c.ray(0, 0).origin.x() - c.ray(5, 0).origin.x(), c.extent * 6 / 4 - pixel, 1e-14);
}

// The sampling paper's 2D set-up: eye at (-9, 0), 120 rays over 30 degrees.
Camera paper_fan() {
  Camera c;
  c.projection = Projection::fan;
  c.eye = Vec3(-9, 0, 0.5);
  c.angle_degrees = 0;
  c.fov_degrees = 30;
  c.width = 120;
  c.height = 1;
  return c;
}

TEST(Camera, FanRaysEquallySpacedInThePlane) {
  const Camera c = paper_fan();
  validate(c);
  std::vector<double> angles;
  for (int i = 0; i < c.width; ++i) {
    const Ray r = c.ray(i, 0);
    EXPECT_EQ(r.origin, c.eye);
    EXPECT_EQ(r.direction.z(), 0);  // in the plane z = eye.z
    EXPECT_NEAR(r.direction.norm(), 1, 1e-15);
    angles.push_back(std::atan2(r.direction.y(), r.direction.x()) / kDeg);
  }
  ASSERT_EQ(angles.size(), 120u);
  EXPECT_NEAR(angles.front(), -15 + 0.125, 1e-12);  // -fov/2 + half a spacing
  EXPECT_NEAR(angles.back(), 15 - 0.125, 1e-12);
  for (std::size_t i = 1; i < angles.size(); ++i)
    EXPECT_NEAR(angles[i] - angles[i - 1], 0.25, 1e-12);  // fov / rays
  // Symmetric about the central direction.
  EXPECT_NEAR(angles[59] + angles[60], 0, 1e-12);
}

TEST(Camera, FanAngleTurnsTheFan) {
  Camera c = paper_fan();
  c.angle_degrees = 90;
  c.width = 3;
  c.fov_degrees = 30;
  validate(c);
  const Ray mid = c.ray(1, 0);
  EXPECT_NEAR((mid.direction - Vec3(0, 1, 0)).norm(), 0, 1e-15);
  EXPECT_NEAR(std::atan2(c.ray(0, 0).direction.y(), c.ray(0, 0).direction.x()) / kDeg, 80, 1e-12);
}

TEST(Camera, DefaultCameraLooksAtTheBoxCentre) {
  Box box{Vec3(0, 0, 0), Vec3(2, 4, 4)};
  const Camera c = default_camera(box);
  validate(c);
  EXPECT_EQ(c.projection, Projection::perspective);
  EXPECT_EQ(c.target, Vec3(1, 2, 2));
  EXPECT_NEAR(c.eye.z(), 2 - 2.5 * 6, 1e-14);  // 2.5 diagonals (|(2, 4, 4)| = 6) along -z
  EXPECT_EQ(c.width, 256);
  EXPECT_EQ(c.height, 256);
  const Ray r = c.ray(128, 128);  // next to the centre
  EXPECT_TRUE(clip(r, box).has_value());
}

void expect_rejected(const Camera& c, const std::string& field) {
  try {
    validate(c);
    ADD_FAILURE() << "accepted a camera with a bad " << field;
  } catch (const CameraError& e) {
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind("camera." + field + ": ", 0), 0u) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  }
}

TEST(Camera, ValidateRejectsBadCameras) {
  EXPECT_NO_THROW(validate(Camera{}));
  Camera c;
  c.width = 0;
  expect_rejected(c, "width");
  c = Camera{};
  c.height = kMaxImageSide + 1;
  expect_rejected(c, "height");
  c = Camera{};
  c.target = c.eye;
  expect_rejected(c, "target");
  c = Camera{};
  c.up = Vec3(0, 0, 2);  // along the view
  expect_rejected(c, "up");
  c.up = Vec3(0, 0, 0);
  expect_rejected(c, "up");
  c = Camera{};
  c.fov_degrees = 180;
  expect_rejected(c, "fov");
  c.fov_degrees = 0;
  expect_rejected(c, "fov");
  c.fov_degrees = NAN;
  expect_rejected(c, "fov");
  c = Camera{};
  c.eye.x() = INFINITY;
  expect_rejected(c, "eye");
  c = Camera{};
  c.projection = Projection::orthographic;
  c.extent = 0;
  expect_rejected(c, "extent");
  c.extent = -1;
  expect_rejected(c, "extent");
  c = paper_fan();
  c.height = 2;
  expect_rejected(c, "height");
  c = paper_fan();
  c.fov_degrees = 0;
  expect_rejected(c, "fov");
  c.fov_degrees = 361;
  expect_rejected(c, "fov");
  // The fan has no target or up: they do not matter.
  c = paper_fan();
  c.target = c.eye;
  c.up = Vec3(0, 0, 0);
  EXPECT_NO_THROW(validate(c));
  c.fov_degrees = 360;
  EXPECT_NO_THROW(validate(c));
}

}  // namespace
}  // namespace vrv
