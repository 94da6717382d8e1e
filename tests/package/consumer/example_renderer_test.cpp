// The example renderer verified in-process against vrv's reference, and its copy with a planted
// half-step offset caught: second order for the midpoint rule, first order for the copy.
#include <algorithm>
#include <cmath>
#include <string>
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
  for (std::size_t i = 0; i < image.pixels.size(); ++i)
    sum += std::pow(image.pixels[i] - reference.pixels[i], 2);
  return std::sqrt(sum / static_cast<double>(image.pixels.size()));
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

// The same two renderers through vrv::verify: the example is named a midpoint rule (inviwo
// placement, alpha rule) and passes; the planted copy fails second order and the half-step
// offset is named.
vrv::VerifyReport verify_renderer(const Scenario& s, vrv::ValueImage (*render)(const vrv::Scene&, const vrv::Camera&, double)) {
  return vrv::verify(s.scene, kSteps, [&](const vrv::Camera& c, double h) { return render(s.scene, c, h); },
                     {.camera = s.camera, .expected_order = 2});
}

TEST(ExampleRenderer, VerifyNamesTheMidpointRule) {
  const vrv::VerifyReport report = verify_renderer(Scenario{}, example::render);
  EXPECT_TRUE(report.pass) << report.verdict.reason;
  ASSERT_FALSE(report.diagnosis.empty());
  // Not to rounding: the example cuts a ray into ceil(length / step) equal segments, which none of
  // vrv's midpoint placements is exactly (inviwo: round(length / step) equal segments; partial and
  // exit_anchored: whole steps and a partial one at the exit or the entry); one of them, ten times
  // nearer than any other placement or rule.
  const auto midpoint_like = [](const vrv::Candidate& c) {
    return (c.placement == "inviwo" || c.placement == "partial" || c.placement == "exit_anchored") &&
           c.rule == "alpha";
  };
  EXPECT_TRUE(midpoint_like(report.diagnosis.front())) << report.diagnosis.front().name;
  for (const vrv::Candidate& c : report.diagnosis)
    if (!midpoint_like(c)) {
      EXPECT_LT(report.diagnosis.front().rms, 0.1 * c.rms) << c.name;
      break;
    }
  EXPECT_TRUE(report.faults.empty()) << report.faults.front().name();
}

TEST(ExampleRenderer, PlantedHalfStepOffsetIsNamedByVerify) {
  const vrv::VerifyReport report = verify_renderer(Scenario{}, example_planted::render);
  EXPECT_FALSE(report.pass);
  EXPECT_EQ(report.verdict.verdict, vrv::Verdict::converges_lower) << report.verdict.reason;
  std::vector<std::string> faults;
  for (const vrv::Fault& f : report.faults) faults.push_back(f.name());
  EXPECT_NE(std::find(faults.begin(), faults.end(), "half-step offset"), faults.end())
      << ::testing::PrintToString(faults);
}

// passes(): a bound's fail level decides, on top of the report's own pass.
TEST(ExampleRenderer, PassesAppliesTheBoundsFailLevels) {
  const vrv::VerifyReport report = verify_renderer(Scenario{}, example::render);
  ASSERT_TRUE(report.pass);
  const double rms = report.channels.back().all().rms;  // the finest image
  vrv::BoundSet bounds;
  bounds.limits[vrv::Bound::rms] = {.fail = rms * 1.01};
  EXPECT_TRUE(vrv::passes(report, bounds));
  bounds.limits[vrv::Bound::rms] = {.warn = rms * 0.5, .fail = rms * 2};
  EXPECT_TRUE(vrv::passes(report, bounds));  // a warning does not fail
  bounds.limits[vrv::Bound::rms] = {.fail = rms * 0.99};
  EXPECT_FALSE(vrv::passes(report, bounds));
  bounds.limits = {{vrv::Bound::min_order, {.fail = 2.5}}};
  EXPECT_FALSE(vrv::passes(report, bounds));
}

// Bad input is the command line's one-line message.
TEST(ExampleRenderer, VerifyRefusesBadInput) {
  const Scenario s;
  const vrv::ValueImage image = example::render(s.scene, s.camera, 0.04);
  EXPECT_THROW(vrv::verify(s.scene, {image, image}, {0.04}), vrv::VerifyInputError);
  EXPECT_THROW(vrv::verify(s.scene, {image, image}, {0.04, 0.04}), vrv::VerifyInputError);
  try {
    vrv::verify(s.scene, {0.04, 0.02}, [&](const vrv::Camera&, double h) {
      return example::render(s.scene, vrv::scene_camera(s.scene, 8, 8), h);
    }, {.camera = s.camera});
    ADD_FAILURE() << "an image of the wrong size was accepted";
  } catch (const vrv::VerifyInputError& e) {
    EXPECT_STREQ(e.what(), "renderer: its image for step 0.04 is 8 x 8, the camera's 24 x 24");
  }
}

}  // namespace
