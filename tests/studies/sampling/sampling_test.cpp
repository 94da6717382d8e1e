// The sampling study's own computations: the rotated set-up, the continuous solution against the
// paper's closed form, error statistics, orders, determinism and the study file's validation.
#include "studies/sampling/fan.h"

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "lib/util/parallel.h"
#include "studies/engine/study_driver.h"
#include "studies/sampling/run.h"

namespace vrv::sampling_study {
namespace {

const std::filesystem::path kStudyFile =
    std::filesystem::path(VRV_SOURCE_DIR) / "studies" / "sampling" / "sampling.toml";

// The study's own file, parsed by the driver; the job is returned so the test can run it.
StudyPlan parse_text(const std::string& text) {
  const toml::table doc = parse_study_toml(text, "test.toml");
  const StudyReader reader("test.toml");
  return find_study_kind("sampling")(StudyInput{doc, reader, "sampling"});
}

std::string study_text() { return read_study_text(kStudyFile); }

// The paper's set-up with a given Scene: the one in the study file.
Scene study_scene() {
  const toml::table doc = parse_study_toml(study_text(), "sampling.toml");
  std::string scene_toml;
  return read_study_scene(StudyReader("sampling.toml"), doc, "", scene_toml);
}

TEST(SamplingStudy, SquareFrameRotatesByMinusAlphaAboutTheCentre) {
  FanSetup s;
  s.centre = {0.5, -0.25};
  s.rotation_degrees = 180.0 / 7;
  const double a = std::numbers::pi / 7;
  const auto p = to_square_frame(s, {-9, 0});
  const double dx = -9 - 0.5, dy = 0.25;
  EXPECT_NEAR(p[0], 0.5 + std::cos(a) * dx + std::sin(a) * dy, 1e-14);
  EXPECT_NEAR(p[1], -0.25 - std::sin(a) * dx + std::cos(a) * dy, 1e-14);
  const auto c = to_square_frame(s, s.centre);
  EXPECT_DOUBLE_EQ(c[0], 0.5);
  EXPECT_DOUBLE_EQ(c[1], -0.25);
}

// A point of the paper's ray i, taken to the square's frame, lies on the study's fan ray i.
TEST(SamplingStudy, FanRaysAreThePapersRaysInTheSquareFrame) {
  FanSetup s;
  const Camera fan = fan_camera(s);
  for (int i : {0, 37, 60, 119}) {
    const double theta = fan_angle_degrees(s, i) * std::numbers::pi / 180;
    const double t = 7.5;
    const auto p = to_square_frame(s, {s.eye[0] + t * std::cos(theta), s.eye[1] + t * std::sin(theta)});
    const Ray ray = fan.ray(i, 0);
    EXPECT_NEAR(ray.at(t).x(), p[0], 1e-13) << i;
    EXPECT_NEAR(ray.at(t).y(), p[1], 1e-13) << i;
    EXPECT_EQ(ray.at(t).z(), 0) << i;
  }
}

// The centre row of an odd-sized image is the fan's plane, its centre pixel looks along the fan's
// central ray, and columns run counter-clockwise like the fan's ray index.
TEST(SamplingStudy, ImageCentreRowLiesInTheFanPlaneInFanOrder) {
  FanSetup s;
  const Camera view = image_camera(s, 101, 101);
  const Ray centre = view.ray(50, 50);
  const Ray central_fan = fan_camera(FanSetup{.rays = 1}).ray(0, 0);
  EXPECT_NEAR((centre.direction - central_fan.direction).norm(), 0, 1e-14);
  const Ray left = view.ray(20, 50), right = view.ray(80, 50);
  EXPECT_NEAR(left.direction.z(), 0, 1e-15);
  EXPECT_NEAR(right.direction.z(), 0, 1e-15);
  EXPECT_GT(std::atan2(right.direction.y(), right.direction.x()),
            std::atan2(left.direction.y(), left.direction.x()));
}

// The continuous solution (vrv's reference on the 5x5 grid) is the closed form for g = 2 tau.
TEST(SamplingStudy, ContinuousSolutionMatchesTheClosedForm) {
  ReferenceAudit audit;
  Study st;
  st.scene = study_scene();
  st.ramp.gradient = Vec3(1.0 / 3, 0, 0);
  st.ramp.offset = 0.5;
  const std::vector<Ray> rays = camera_rays(fan_camera(st.setup));
  const std::vector<ContinuousRay> truth = continuous_rays(st.scene, rays, 1e-13, audit);
  EXPECT_EQ(audit.counts().rays, static_cast<long>(rays.size()));  // every ray's truth, once
  long hit = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    EXPECT_NEAR(truth[i].value, closed_form(st, rays[i], 2.0), 2e-13) << i;
    EXPECT_LE(truth[i].estimate, 1e-13);
    hit += truth[i].chord > 0;
  }
  // Half-diagonal 1.5 sqrt 2 from 9 away spans about +-13.6 degrees of the fan's +-15: most rays hit.
  EXPECT_GT(hit, 100);
  EXPECT_LT(hit, 120);
}

TEST(SamplingStudy, ErrorStatsSkipMissesAndCountDroppedRays) {
  const std::vector<ContinuousRay> truth{{0, 0, 0}, {1.0, 0.5, 0}, {0.1, 0.2, 0}, {2.0, 1.0, 0}};
  const std::vector<RayValue> rays{{0.3, 0}, {0.6, 4}, {0, 0}, {0.9, 8}};
  const FanStats st = ray_error_stats(truth, rays);
  EXPECT_EQ(st.error.count, 3);
  EXPECT_EQ(st.dropped, 1);
  EXPECT_DOUBLE_EQ(st.error.max, 0.2);
  EXPECT_NEAR(st.error.mean, (0.1 + 0.2 + 0.1) / 3, 1e-16);
  EXPECT_DOUBLE_EQ(st.mean_samples, 4);
  EXPECT_EQ(st.nonfinite, 0);
  EXPECT_EQ(ray_error_stats(truth, {{0, 0}, {NAN, 1}, {0, 0}, {1, 1}}).nonfinite, 1);
}

TEST(SamplingStudy, OrderOverRatesIsTheSlopeAgainstOneOverRate) {
  EXPECT_NEAR(order_over_rates({1, 2, 4, 8}, {0.5, 0.25, 0.125, 0.0625}), 1, 1e-12);
  EXPECT_NEAR(order_over_rates({1, 4, 16}, {1, 1.0 / 16, 1.0 / 256}), 2, 1e-12);
  EXPECT_TRUE(std::isnan(order_over_rates({1, 2}, {0.1, 0})));
}

// Listing 3 drops the short corner chords of this set-up; Listing 4 keeps them (Fig. 2c vs 2d).
TEST(SamplingStudy, EntryExitDropsCornerRaysAndCornerKeepsThem) {
  ReferenceAudit audit;
  const Scene scene = study_scene();
  const FanSetup s;
  const Camera fan = fan_camera(s);
  const std::vector<Ray> rays = camera_rays(fan);
  const std::vector<ContinuousRay> truth = continuous_rays(scene, rays, 1e-13, audit);
  const auto plain = discrete_rays(scene, rays, strategy_config(scene, SegmentRule::riemann, Strategy::entry_exit, 1, fan.eye));
  const auto corner =
      discrete_rays(scene, rays, strategy_config(scene, SegmentRule::riemann, Strategy::entry_exit_corner, 1, fan.eye));
  EXPECT_GE(ray_error_stats(truth, plain).dropped, 1);
  EXPECT_EQ(ray_error_stats(truth, corner).dropped, 0);
}

// With g = 2 tau the alpha rule composites to 2 (1 - exp(-sum tau dx)); Listing 4 tiles every chord
// and samples the midpoints, which integrates the linear tau exactly.  Listing 2 does not tile.
TEST(SamplingStudy, AlphaWithTheCornerPlacementIsExactForProportionalTransfer) {
  ReferenceAudit audit;
  const Scene scene = study_scene();
  const Camera fan = fan_camera(FanSetup{});
  const std::vector<Ray> rays = camera_rays(fan);
  const std::vector<ContinuousRay> truth = continuous_rays(scene, rays, 1e-13, audit);
  for (double rate : {1.0, 3.0, 16.0}) {
    const auto corner = discrete_rays(
        scene, rays, strategy_config(scene, SegmentRule::alpha, Strategy::entry_exit_corner, rate, fan.eye));
    EXPECT_LT(ray_error_stats(truth, corner).error.max, 1e-13) << rate;
    const auto entry =
        discrete_rays(scene, rays, strategy_config(scene, SegmentRule::alpha, Strategy::entry, rate, fan.eye));
    EXPECT_GT(ray_error_stats(truth, entry).error.max, 1e-3) << rate;
  }
}

TEST(SamplingStudy, RaysAreBitwiseIdenticalForOneAndTwoThreads) {
  ReferenceAudit audit;
  const Scene scene = study_scene();
  const Camera fan = fan_camera(FanSetup{});
  const std::vector<Ray> rays = camera_rays(fan);
  const DiscreteConfig c = strategy_config(scene, SegmentRule::riemann, Strategy::eye, 4, fan.eye);
  std::vector<RayValue> one, two;
  std::vector<ContinuousRay> t1, t2;
  {
    const ThreadLimit limit(1);
    one = discrete_rays(scene, rays, c);
    t1 = continuous_rays(scene, rays, 1e-13, audit);
  }
  {
    const ThreadLimit limit(2);
    two = discrete_rays(scene, rays, c);
    t2 = continuous_rays(scene, rays, 1e-13, audit);
  }
  for (std::size_t i = 0; i < rays.size(); ++i) {
    EXPECT_EQ(one[i].value, two[i].value) << i;
    EXPECT_EQ(one[i].samples, two[i].samples) << i;
    EXPECT_EQ(t1[i].value, t2[i].value) << i;
  }
}

void expect_rejected(const std::string& from, const std::string& to, const std::string& message) {
  std::string text = study_text();
  const auto at = text.find(from);
  ASSERT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
  try {
    parse_text(text);
    ADD_FAILURE() << "accepted: " << to;
  } catch (const StudyFileError& e) {
    EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  }
}

TEST(SamplingStudy, StudyFileIsValidatedKeyByKey) {
  EXPECT_NO_THROW(parse_text(study_text()));
  expect_rejected("rays = 120", "rays = 120\nbogus = 1", "test.toml: setup.bogus: unknown key");
  expect_rejected("\"entry_exit_corner\"]\n\n", "\"vtk\"]\n\n", "strategies[3]: 'vtk' is not taken here (one of eye, entry, entry_exit, entry_exit_corner)");
  expect_rejected("rates = [1.0, 4.0, 16.0]", "rates = [1.0, 3.0]", "curves.rates: rate 3 is not among");
  expect_rejected("rates = [1.0, 2.0, 4.0", "rates = [2.0, 1.0, 4.0", "orders.rates: must be strictly");
  expect_rejected("eye = [-9.0, 0.0]", "eye = [-9.0, 0.0, 1.0]", "setup.eye: expected two numbers");
  expect_rejected("closed_form_kappa = 2.0", "closed_form_kappa = 3.0", "checks.closed_form_kappa: needs");
  expect_rejected("rules = [\"riemann\", \"alpha\"]", "rules = [\"alpha\"]",
                  "orders.rules: must start with riemann");
  expect_rejected("rules = [\"riemann\", \"alpha\"]", "rules = [\"riemann\", \"trapezoid\"]",
                  "orders.rules[1]: expected a sample rule");
  expect_rejected("rule = \"alpha\"\nstrategies = [\"eye\", \"entry\"]",
                  "rule = \"moreland\"\nstrategies = [\"eye\", \"entry\"]",
                  "checks.order[1].rule: not among orders.rules");
  expect_rejected("max_error = 1e-12", "max_error = 1e-12\nbogus = 2", "checks.exact[0].bogus: unknown key");
  expect_rejected("keeps_every_ray = [\"entry_exit_corner\"]", "keeps_every_ray = [\"step\"]",
                  "checks.keeps_every_ray[0]");
  // An error bound no result could meet is refused (it failed after the run, exit 1).
  expect_rejected("max_error = 1e-12", "max_error = -1e-12", "test.toml: checks.exact[0].max_error: must be >= 0, got -1e-12");
  // A fan turned away from the square: every order was NaN after the run (exit 1).
  // One ray that touches the square's corner (a chord of length 0) measures nothing either.
  expect_rejected("eye = [-9.0, 0.0]\ncentre = [0.0, 0.0]\nrotation_degrees = 25.714285714285715   # 180/7 = pi/7\n"
                  "angle_degrees = 0.0\nfov_degrees = 30.0\nrays = 120\n",
                  "eye = [-3.0, 2.220446049250313e-16]\ncentre = [0.0, 0.0]\nrotation_degrees = 0.0\n"
                  "angle_degrees = 45.0\nfov_degrees = 1.0\nrays = 1\n",
                  "test.toml: setup: none of the 1 fan rays meets the volume");
  expect_rejected("angle_degrees = 0.0", "angle_degrees = 180.0",
                  "test.toml: setup: none of the 120 fan rays meets the volume (see eye, centre, angle_degrees and "
                  "fov_degrees): there is nothing to measure");
}

}  // namespace
}  // namespace vrv::sampling_study
