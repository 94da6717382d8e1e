// lib/verify on a shaded scene ([shading], docs/shading.md): images of a toy shading renderer that
// is not vrv's (its own loop, its own central differences and Blinn-Phong term), judged against the
// shaded reference; the diagnosis names the renderer's gradient scheme, and a scheme that is not
// the field's exact gradient is named as the images' floor.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <gtest/gtest.h>

#include "lib/scene_file.h"
#include "lib/verify.h"
#include "tests/lib/verify/verify_toy.h"

namespace vrv::verify_shading_test {
namespace {

using verify_toy::fault_of;

// Marschner-Lobb at fM = 1 seen from the side, so that the rays stay away from where its gradient
// nearly vanishes (the z faces, and cylinders of zero radial slope, where the normal turns over
// about 0.002 at fM = 6): there S is nearly a jump at these steps and the order falls toward 1.
constexpr const char* kScene = R"(
[volume]
min = [-1.0, -1.0, -1.0]
max = [1.0, 1.0, 1.0]
dims = [32, 32, 32]
[field]
kind = "marschner_lobb"
fM = 1.0
[transfer]
emission = [[0.0, 0.0], [1.0, 1.0]]
extinction = [[0.0, 0.0], [1.0, 2.0]]
[background]
intensity = 0.2
[shading]
light = [0.3, 0.5, -0.8]
two_sided = false
[camera]
eye = [-4.0, 0.5, 0.3]
target = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fov = 20.0
width = 16
height = 16
)";

const Scene& shaded_scene() {
  static const Scene scene = parse_scene(kScene, "shaded.toml");
  return scene;
}

// The toy's Blinn-Phong factor for the scene's [shading] (the defaults but the light, one-sided: a
// two-sided normal's flips are jumps of S, which make a midpoint rule first order): the normal the
// negative gradient.
double blinn_phong(Vec3 g, const Vec3& toward_eye) {
  const Shading& s = *shaded_scene().shading;
  if (g.norm() == 0) return s.ambient;
  const Vec3 n = -g.normalized();
  const Vec3 l = s.light->normalized();
  const Vec3 h = (l + toward_eye).normalized();
  return s.ambient + s.diffuse * std::max(0.0, n.dot(l)) + s.specular * std::pow(std::max(0.0, n.dot(h)), s.shininess);
}

// The toy renderer: the clipped ray cut into round(length / step) equal steps, one sample at each
// step's middle, its emission times the Blinn-Phong factor of the gradient by central differences
// of offset d, composited front to back with opacity 1 - exp(-tau h).
std::vector<double> toy_image(double step, double d) {
  const Scene& scene = shaded_scene();
  const Camera& camera = *scene.camera;
  std::vector<double> out;
  visit_field(scene, [&](const auto& field) {
    const auto f = [&](const Vec3& p) { return field.value(p); };
    for (int y = 0; y < camera.height; ++y)
      for (int x = 0; x < camera.width; ++x) {
        const Ray ray = camera.ray(x, y);
        double colour = 0, transparency = 1;
        if (const auto iv = clip(ray, scene.box); iv && iv->t1 > iv->t0) {
          const long n = std::max(1L, std::lround((iv->t1 - iv->t0) / step));
          const double h = (iv->t1 - iv->t0) / static_cast<double>(n);
          for (long k = 0; k < n; ++k) {
            const Vec3 p = ray.at(iv->t0 + (static_cast<double>(k) + 0.5) * h);
            const Vec3 g((f(p + Vec3(d, 0, 0)) - f(p - Vec3(d, 0, 0))) / (2 * d),
                         (f(p + Vec3(0, d, 0)) - f(p - Vec3(0, d, 0))) / (2 * d),
                         (f(p + Vec3(0, 0, d)) - f(p - Vec3(0, 0, d))) / (2 * d));
            const double v = f(p), tau = scene.transfer.extinction(v);
            const double emitted = scene.transfer.emission(v) * blinn_phong(g, -ray.direction);
            const double alpha = -std::expm1(-tau * h);
            colour += transparency * (tau > 0 ? emitted / tau * alpha : emitted * h);
            transparency *= 1 - alpha;
          }
        }
        out.push_back(colour + transparency * scene.background);
      }
  });
  return out;
}

std::vector<ImageWithStep> toy_images(double d) {
  std::vector<ImageWithStep> out;
  for (double h : {0.1, 0.05, 0.025}) {
    ChannelImage im(ImageF64(16, 16, toy_image(h, d)));
    im.pixel_type = "double";
    out.push_back({fmt::format("toy_{}", h), h, std::move(im)});
  }
  return out;
}

std::string failures(const VerifyReport& r) { return fmt::format("{}", fmt::join(r.failures, "; ")); }

// Gradients by central differences one voxel apart (2 / 32, what GPU raycasters do): the nearest
// model takes them, the reference's exact gradient is far from them, and the floor is named.
TEST(VerifyShading, CentralDifferencesAreTheFloor) {
  const VerifyReport r = verify_images(shaded_scene(), toy_images(2.0 / 32), verify_toy::options());
  ASSERT_FALSE(r.diagnosis.empty());
  const Candidate& best = r.diagnosis.front();
  EXPECT_EQ(best.gradient, "central") << best.name;
  EXPECT_NE(best.name.find("offset one voxel (0.0625)"), std::string::npos) << best.name;
  EXPECT_LT(best.rms, 1e-10) << best.name;
  const Fault* floor = fault_of(r, FaultKind::gradient_floor);
  ASSERT_NE(floor, nullptr) << failures(r);
  EXPECT_EQ(floor->behaviour, "gradient central");
  EXPECT_FALSE(r.pass) << "a floor of the gradient scheme cannot converge at order 2 to the exact-gradient reference";
  EXPECT_TRUE(r.reference.missed == 0) << failures(r);
}

// Half a voxel: the offset is named as a number.
TEST(VerifyShading, AnotherOffsetIsNamed) {
  const VerifyReport r = verify_images(shaded_scene(), toy_images(1.0 / 32), verify_toy::options());
  ASSERT_FALSE(r.diagnosis.empty());
  EXPECT_EQ(r.diagnosis.front().gradient, "central 0.03125") << r.diagnosis.front().name;
  EXPECT_LT(r.diagnosis.front().rms, 1e-10);
  EXPECT_NE(fault_of(r, FaultKind::gradient_floor), nullptr) << failures(r);
}

// Nearly exact gradients (differences 1e-6 apart): second order to the shaded reference, the exact
// gradient nearest, and no floor named.
TEST(VerifyShading, ExactGradientsConverge) {
  const VerifyReport r = verify_images(shaded_scene(), toy_images(1e-6), verify_toy::options());
  EXPECT_TRUE(r.pass) << failures(r);
  ASSERT_FALSE(r.diagnosis.empty());
  EXPECT_EQ(r.diagnosis.front().gradient, "analytic") << r.diagnosis.front().name;
  EXPECT_EQ(fault_of(r, FaultKind::gradient_floor), nullptr);
}

// A projection of a shaded scene is refused, naming the shading.
TEST(VerifyShading, ProjectionRefused) {
  VerifyOptions o;
  o.mode = ProjectionMode::mip;
  try {
    verify_images(shaded_scene(), toy_images(1e-6), o);
    FAIL() << "verified a shaded scene's projection";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("shading"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vrv::verify_shading_test
