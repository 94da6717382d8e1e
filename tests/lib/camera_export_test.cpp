#include "lib/camera_export.h"

#include <gtest/gtest.h>

#include "lib/io/npy.h"

namespace vrv {
namespace {

TEST(CameraExport, RaysNpyEqualsTheCameraRaysBitwise) {
  for (Projection p : {Projection::perspective, Projection::orthographic}) {
    Camera c;
    c.projection = p;
    c.eye = Vec3(0.3, -4, 1.7);
    c.up = Vec3(0.1, 0, 1);
    c.width = 7;
    c.height = 5;
    validate(c);
    const NpyArray a = parse_npy(rays_npy(c), "rays.npy");
    EXPECT_EQ(a.dtype, "<f8");
    EXPECT_EQ(a.shape, (std::vector<std::size_t>{5, 7, 2, 3}));
    for (int y = 0; y < c.height; ++y)
      for (int x = 0; x < c.width; ++x) {
        const Ray r = c.ray(x, y);
        const double* q = &a.values[(static_cast<std::size_t>(y) * c.width + x) * 6];
        for (int i = 0; i < 3; ++i) {
          EXPECT_EQ(q[i], r.origin[i]);
          EXPECT_EQ(q[3 + i], r.direction[i]);
        }
      }
  }
}

TEST(CameraExport, JsonRebuildsTheTopLeftPixelRay) {
  Camera c;
  c.eye = Vec3(1, 2, -5);
  c.target = Vec3(0.5, 0, 0);
  c.width = 8;
  c.height = 4;
  const auto j = camera_json(c);
  EXPECT_EQ(j["projection"], "perspective");
  EXPECT_EQ(j["width"], 8);
  EXPECT_EQ(j["fov_degrees"], 40.0);
  // The convention as written: u, v of pixel (0, 0), then the direction from the JSON frame.
  const auto v3 = [&](const char* k) { return Vec3(j["frame"][k][0], j["frame"][k][1], j["frame"][k][2]); };
  const double half_h = std::tan(40.0 * M_PI / 360), u = 2 * 0.5 / 8 - 1, w = 1 - 2 * 0.5 / 4;
  const Vec3 d = (v3("forward") + u * half_h * 2 * v3("right") + w * half_h * v3("up")).normalized();
  EXPECT_NEAR((d - c.ray(0, 0).direction).norm(), 0, 1e-15);
}

}  // namespace
}  // namespace vrv
