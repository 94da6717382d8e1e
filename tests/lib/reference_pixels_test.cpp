#include "lib/reference_pixels.h"

#include <vector>

#include <gtest/gtest.h>

#include "lib/scene_file.h"

namespace vrv {
namespace {

// Each position gets its own pixel's integral, for the whole image and for a subset.
TEST(ReferencePixels, EveryPositionIsItsPixelsIntegral) {
  const Scene scene = default_scene();
  Camera camera = default_camera(scene.box);
  camera.width = 9;
  camera.height = 7;
  const ReferenceOptions options{1e-8};
  std::vector<ReferenceResult> all(static_cast<std::size_t>(pixel_count(camera)));
  reference_pixels(scene, camera, options, [&](long i, const ReferenceResult& r) { all[i] = r; });
  const std::vector<long> subset{62, 0, 31};
  std::vector<ReferenceResult> some(subset.size());
  reference_pixels(scene, camera, options, [&](long k, const ReferenceResult& r) { some[k] = r; }, {}, subset);
  visit_field(scene, [&](const auto& field) {
    for (long i = 0; i < pixel_count(camera); ++i) {
      const ReferenceResult r =
          integrate_reference(field, scene.box, scene.transfer, scene.background, pixel_ray(camera, i), options);
      EXPECT_EQ(all[i].value, r.value) << i;
      EXPECT_EQ(all[i].error_estimate, r.error_estimate) << i;
      EXPECT_EQ(all[i].evaluations, r.evaluations) << i;
    }
  });
  for (std::size_t k = 0; k < subset.size(); ++k) EXPECT_EQ(some[k].value, all[subset[k]].value) << k;
}

}  // namespace
}  // namespace vrv
