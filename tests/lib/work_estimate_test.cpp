#include "lib/work_estimate.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "lib/camera.h"
#include "lib/discrete_raycast.h"
#include "lib/discrete_raycast_impl.h"
#include "lib/reference_integrator.h"

namespace vrv {
namespace {

TransferFunction ramp_transfer() {
  return TransferFunction::emission_extinction(PiecewiseLinear({{0, 0}, {1, 1}}), PiecewiseLinear({{0, 0.1}, {1, 2}}));
}

Scene ml_scene(double fM) {
  Scene s;
  s.field = MarschnerLobb{fM, 0.25};
  s.transfer = ramp_transfer();
  return s;
}

// Rays from a sphere around the box through random points of it: long, short and grazing chords.
std::vector<Ray> random_rays(const Box& box, int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Ray> rays;
  for (int i = 0; i < n; ++i) {
    const double z = 2 * u(rng) - 1, phi = 2 * std::numbers::pi * u(rng), r = std::sqrt(1 - z * z);
    const Vec3 from = 4 * Vec3(r * std::cos(phi), r * std::sin(phi), z);
    const Vec3 to = box.min + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(box.extent());
    rays.push_back({from, (to - from).normalized()});
  }
  return rays;
}

DiscreteConfig step_config(SegmentRule rule, double h, int oversample, Correction correction, bool centred) {
  DiscreteConfig c;
  c.rule = rule;
  c.sampling.strategy = Strategy::step;
  c.sampling.step = h;
  c.oversample = oversample;
  c.correction = correction;
  c.centred_oversamples = centred;
  return c;
}

// The discrete estimate is the raycast's own sample count on a given ray, and the diagonal's
// is at least every ray's.
TEST(WorkEstimate, DiscreteSamplesAreTheRaycastsOwnAndTheDiagonalBoundsThem) {
  const Scene scene = ml_scene(6);
  const Correction none = Correction::none, lee = Correction::lee_newman;
  for (const DiscreteConfig& c :
       {step_config(SegmentRule::riemann, 0.01, 1, none, false), step_config(SegmentRule::trapezoid, 0.01, 1, none, false),
        step_config(SegmentRule::moreland, 0.003, 4, none, true), step_config(SegmentRule::alpha, 0.003, 4, lee, true),
        step_config(SegmentRule::alpha, 0.003, 5, lee, false)}) {
    const double diagonal = discrete_samples(c, scene);
    const double lookups = c.correction == lee && c.centred_oversamples ? 1 + 1.0 / c.oversample : 1;
    EXPECT_NEAR(diagonal, std::sqrt(12.0) / c.sampling.step * c.oversample * lookups, 3 * c.oversample);
    for (const Ray& ray : random_rays(scene.box, 200, 1)) {
      const double estimate = discrete_samples(c, scene, ray);
      EXPECT_EQ(estimate, static_cast<double>(discrete_raycast(scene, ray, c).samples));
      EXPECT_LE(estimate, diagonal);
    }
  }
}

// The oversampled count is found from its estimate, not by stepping along the ray: the same count
// as stepping (checked on random plans), and a run of 3.5e14 samples is estimated at once.
TEST(WorkEstimate, OversampledCountsAreTheSteppedOnesWithoutTheLoop) {
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < 2000; ++i) {
    SamplePlan plan{-1 + u(rng), 1e-3 + u(rng) * 0.1, 1 + 3 * u(rng), 0};
    while (plan.t(plan.count) < plan.t_end) ++plan.count;
    for (const int N : {1, 2, 3, 7, 64})
      for (const bool centred : {false, true}) {
        const SamplePlan fine = detail::oversampled(plan, N, centred);
        long stepped = 0;
        while (fine.t(stepped) < fine.t_end) ++stepped;
        ASSERT_EQ(fine.count, stepped) << i << " N " << N;
      }
  }
  const Scene scene = ml_scene(6);
  EXPECT_NEAR(discrete_samples(step_config(SegmentRule::alpha, 1e-11, 1024, Correction::none, false), scene),
              std::sqrt(12.0) / 1e-11 * 1024, 1e-6 * std::sqrt(12.0) / 1e-11 * 1024);
}

// Fields of known degree: one panel per stretch, exactly the integrator's count when it does not
// stop early.
TEST(WorkEstimate, KnownDegreeFieldsAreCountedExactly) {
  Scene scene = ml_scene(6);
  scene.field = make_grid(scene.box, MarschnerLobb{6, 0.25}, {17, 9, 33}, GridLayout::node, Interpolation::trilinear);
  ReferenceOptions whole;
  whole.stop_when_opaque = false;
  const double diagonal = reference_evaluations(scene, 1e-12);
  EXPECT_LE(diagonal, grid_reference_evaluations({17, 9, 33}, 3));
  for (const Ray& ray : random_rays(scene.box, 200, 2)) {
    const double estimate = reference_evaluations(scene, ray, 1e-12);
    EXPECT_EQ(estimate, static_cast<double>(integrate_reference(scene, ray, whole).evaluations));
    EXPECT_LE(estimate, grid_reference_evaluations({17, 9, 33}, 3));
  }
  scene.field = LinearRamp{};
  EXPECT_EQ(reference_evaluations(scene, 1e-12), 2);
}

// Analytic fields: the diagonal's first panels against the integrator's mean work on random rays
// (which adds refinement and merges panels): an upper estimate that is not absurd.
TEST(WorkEstimate, AnalyticFieldsDiagonalEstimateIsWithinAFewTimesTheMeanWork) {
  for (const double fM : {2.0, 6.0, 24.0})
    for (const double tol : {1e-6, 1e-10, 1e-12}) {
      const Scene scene = ml_scene(fM);
      double sum = 0;
      const std::vector<Ray> rays = random_rays(scene.box, 200, 3);
      for (const Ray& ray : rays) sum += static_cast<double>(integrate_reference(scene, ray, {tol}).evaluations);
      const double mean = sum / static_cast<double>(rays.size());
      const double estimate = reference_evaluations(scene, tol);
      EXPECT_GE(estimate, mean) << "fM " << fM << " tol " << tol;
      EXPECT_LE(estimate, 5 * mean) << "fM " << fM << " tol " << tol;
    }
}

// A field too fast for any run is capped at the integrator's own work cap, never overflows.
TEST(WorkEstimate, HugeBandwidthIsCappedAtTheWorkCap) {
  EXPECT_EQ(reference_evaluations(ml_scene(1e300), 1e-12), static_cast<double>(detail::kMaxEvaluations));
  Scene scene = ml_scene(6);
  EXPECT_EQ(reference_evaluations(scene, Ray{{10, 10, 10}, {1, 0, 0}}, 1e-12), 0);  // a miss
}

TEST(WorkEstimate, TheLimitThatAllowsAnEstimateIsRoundedUp) {
  EXPECT_EQ(work_limit_allowing(2.01e9), "2.1e+09");
  EXPECT_EQ(work_limit_allowing(2e9), "2e+09");
  EXPECT_EQ(work_limit_allowing(123), "1.3e+02");
}

// What verify and gate compare with --max-work (issue 22): every pixel's work for an image of at
// most 64 x 64 pixels, and the sub-grid's scaled for a larger one (a 4096^2 image, at once).
TEST(WorkEstimate, CameraWorkIsEveryPixelsUpTo64SquaredAndScaledAbove) {
  const Scene scene = ml_scene(6);
  Camera camera = default_camera(scene.box);
  camera.width = 40, camera.height = 24;
  double exact = 0;
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) exact += reference_evaluations(scene, camera.ray(x, y), 1e-10);
  EXPECT_DOUBLE_EQ(camera_work(scene, camera, 1e-10), exact);
  const DiscreteConfig config = step_config(SegmentRule::alpha, 0.01, 1, Correction::none, false);
  double samples = 0;
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) samples += discrete_samples(config, scene, camera.ray(x, y));
  EXPECT_DOUBLE_EQ(camera_work(scene, camera, 0, &config), samples);
  camera.width = camera.height = 4096;
  const double big = camera_work(scene, camera, 1e-10);
  EXPECT_GT(big, 0.3 * exact * 4096 * 4096 / (40 * 24));
  EXPECT_LT(big, 3 * exact * 4096 * 4096 / (40 * 24));
}

}  // namespace
}  // namespace vrv
