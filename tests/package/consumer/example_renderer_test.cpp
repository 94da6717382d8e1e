// The example renderer verified in-process against vrv's reference, and its copy with a planted
// half-step offset caught: second order for the midpoint rule, first order for the copy.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <vrv/vrv.h>

#include "example_renderer.h"
#include "example_renderer_planted.h"

namespace {

const std::vector<double> kSteps{0.08, 0.04, 0.02, 0.01};

struct Scenario {
  vrv::Scene scene = vrv::default_scene();
  vrv::Camera camera = vrv::scene_camera(scene, 24, 24);
  vrv::ValueImage reference = vrv::render_reference_image(scene, camera, {1e-10});
};

double rms_error(const vrv::ValueImage& image, const vrv::ValueImage& reference) {
  double sum = 0;
  for (std::size_t i = 0; i < image.values.size(); ++i)
    sum += std::pow(image.values[i] - reference.values[i], 2);
  return std::sqrt(sum / static_cast<double>(image.values.size()));
}

// Least-squares slope of log(RMS error) against log(step).
template <class Render>
double observed_order(const Scenario& s, Render render) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (double h : kSteps) {
    const double x = std::log(h), y = std::log(rms_error(render(s.scene, s.camera, h), s.reference));
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  const double n = static_cast<double>(kSteps.size());
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

TEST(ExampleRenderer, ConvergesAtSecondOrder) {
  const Scenario s;
  EXPECT_NEAR(observed_order(s, example::render), 2.0, 0.2);
  EXPECT_LT(rms_error(example::render(s.scene, s.camera, 0.01), s.reference), 1e-4);
}

TEST(ExampleRenderer, PlantedHalfStepOffsetIsCaught) {
  const Scenario s;
  EXPECT_NEAR(observed_order(s, example_planted::render), 1.0, 0.2);
}

}  // namespace
