// What a renderer's test suite writes: its convergence order asserted in three lines.  The
// example renderer (tests/package/example_renderer) stands in for yours.
#include <gtest/gtest.h>
#include <vrv/vrv.h>

#include "example_renderer.h"

TEST(MyRenderer, ConvergesAtSecondOrder) {
  const vrv::Scene scene = vrv::default_scene();
  const vrv::VerifyReport report = vrv::verify(scene, {0.08, 0.04, 0.02, 0.01}, [&](const vrv::Camera& camera, double step) { return example::render(scene, camera, step); }, {.camera = vrv::scene_camera(scene, 24, 24), .expected_order = 2});
  EXPECT_TRUE(report.pass) << report.verdict.reason;
}
