// detail::RayAccumulator<N> (lib/ray_accumulator.h): channels in lockstep under one extinction.
// The per-channel truths are tests/lib/reference_color (mpmath, each channel alone) and
// tests/lib/reference_alpha; here, what lockstep itself must keep:
//   - channels that differ (emission, breakpoints, jumps, backgrounds) are each the same integral
//     as their own grey ray: the two agree within the sum of their estimates, each within tol;
//   - a channel that stops (opaque for it) keeps the depth, value and estimate of where it stopped
//     while the others go on;
//   - channels whose extinctions differ are refused.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <stdexcept>
#include <variant>
#include <vector>

#include "lib/grid_field.h"
#include "lib/reference_channels.h"
#include "lib/reference_integrator.h"
#include "lib/scene.h"
#include "lib/scene_file.h"

namespace vrv::ray_accumulator_test {
namespace {

TransferFunction with_emission(std::vector<ControlPoint> emission, const PiecewiseLinear& extinction) {
  return TransferFunction::emission_extinction(PiecewiseLinear(std::move(emission)), extinction);
}

// Three channels of different emission, knots and jumps under one extinction with a jump.
std::array<TransferFunction, 3> distinct_channels() {
  const PiecewiseLinear extinction({{0, 0.3}, {0.45, 2.5}, {0.45, 0.8}, {1, 1.6}});
  return {with_emission({{0, 0}, {1, 2}}, extinction), with_emission({{0, 1.2}, {0.3, 0.1}, {1, 0.6}}, extinction),
          with_emission({{0, 0.1}, {0.6, 0.1}, {0.6, 1.9}, {1, 0.2}}, extinction)};
}

std::vector<Ray> some_rays() {
  std::vector<Ray> rays;
  for (const Vec3& d : {Vec3(0.1, 0.2, 1), Vec3(1, -0.3, 0.2), Vec3(-0.4, 1, 0.7), Vec3(0.6, 0.6, -0.5)})
    rays.push_back(make_ray(-3 * d.normalized() + Vec3(0.05, -0.1, 0.02), d));
  return rays;
}

// Each channel of `scene`'s colour against its own grey ray: the same integral to within both
// estimates, each meeting tol.
void expect_each_channel_its_grey_ray(Scene scene, double tol) {
  const ColorChannels color = *scene.color;
  Scene grey = scene;
  grey.color.reset();
  for (const Ray& ray : some_rays()) {
    const ChannelsReferenceResult three = integrate_color_reference(scene, ray, {tol});
    for (int c = 0; c < 3; ++c) {
      grey.transfer = color.transfer[c];
      grey.background = color.background[c];
      const ReferenceResult one = integrate_reference(grey, ray, {tol});
      const ReferenceResult& lock = three.channel[c];
      EXPECT_TRUE(lock.tolerance_met && one.tolerance_met) << c;
      EXPECT_LE(std::abs(lock.value - one.value), lock.error_estimate + one.error_estimate)
          << "channel " << c << " ray " << ray.direction.transpose();
    }
  }
}

TEST(RayAccumulator, DistinctChannelsAreEachTheirGreyRayOnAnAnalyticField) {
  Scene scene = default_scene();
  const auto tf = distinct_channels();
  scene.color = ColorChannels{{tf[0], tf[1], tf[2]}, {0.0, 0.25, 1.5}};
  expect_each_channel_its_grey_ray(scene, 1e-12);
  expect_each_channel_its_grey_ray(scene, 1e-9);
}

TEST(RayAccumulator, DistinctChannelsAreEachTheirGreyRayOnAGrid) {
  Scene scene = default_scene();
  scene.field = make_grid(scene.box, MarschnerLobb{}, {17, 17, 17}, GridLayout::node, Interpolation::trilinear);
  const auto tf = distinct_channels();
  scene.color = ColorChannels{{tf[0], tf[1], tf[2]}, {0.5, 0.0, 0.0}};
  expect_each_channel_its_grey_ray(scene, 1e-12);
}

// Thick enough to stop: a channel over a huge background needs e^-Phi far smaller than one over
// none, so it goes on integrating after the other has stopped.
TEST(RayAccumulator, AChannelThatStopsKeepsWhereItStopped) {
  const Scene scene = default_scene();
  const auto& field = std::get<MarschnerLobb>(scene.field);
  const PiecewiseLinear extinction({{0, 40}, {1, 60}});
  const TransferFunction tf = with_emission({{0, 1}, {1, 3}}, extinction);
  const std::array<ReferenceChannel, 2> channels{{{&tf, 0.0}, {&tf, 1e12}}};
  for (const Ray& ray : some_rays()) {
    const ChannelsReferenceResult two = integrate_channels_reference(field, scene.box,
                                                                     channels, ray, {1e-12});
    ASSERT_EQ(two.count, 2);
    const ReferenceResult& early = two.channel[0];
    const ReferenceResult& late = two.channel[1];
    EXPECT_TRUE(early.stopped_early);
    EXPECT_LT(early.optical_depth, late.optical_depth);
    for (int c = 0; c < 2; ++c) {
      const ReferenceResult one = integrate_reference(field, scene.box, tf,
                                                      channels[c].background, ray, {1e-12});
      const ReferenceResult& lock = two.channel[c];
      EXPECT_TRUE(lock.tolerance_met) << c;
      EXPECT_EQ(lock.stopped_early, one.stopped_early) << c;
      EXPECT_LE(std::abs(lock.value - one.value), lock.error_estimate + one.error_estimate) << c;
    }
  }
}

// A channel with g = kappa tau keeps its exact route (kappa (1 - e^-dPhi) from the depth) beside a
// channel that needs the rule: its estimate stays near its grey ray's, not the rule's.
TEST(RayAccumulator, AProportionalChannelKeepsItsExactRouteBesideAnother) {
  const Scene scene = default_scene();
  const auto& field = std::get<MarschnerLobb>(scene.field);
  const PiecewiseLinear extinction({{0, 0.5}, {1, 3}});
  const TransferFunction proportional = with_emission({{0, 0.5 * 0.7}, {1, 3 * 0.7}}, extinction);
  const TransferFunction other = with_emission({{0, 2}, {0.5, 0.1}, {1, 1}}, extinction);
  ASSERT_TRUE(proportional.emission_per_extinction());
  const std::array<ReferenceChannel, 2> channels{{{&proportional, 0.0}, {&other, 0.0}}};
  for (const Ray& ray : some_rays()) {
    const ChannelsReferenceResult two = integrate_channels_reference(field, scene.box, channels, ray, {1e-12});
    const ReferenceResult one = integrate_reference(field, scene.box, proportional, 0.0, ray, {1e-12});
    EXPECT_LE(std::abs(two.channel[0].value - one.value), two.channel[0].error_estimate + one.error_estimate);
    EXPECT_LE(two.channel[0].error_estimate, 2 * one.error_estimate);
  }
}

TEST(RayAccumulator, ChannelsOfDifferentExtinctionsAreRefused) {
  const Scene scene = default_scene();
  const auto& field = std::get<MarschnerLobb>(scene.field);
  const TransferFunction a = with_emission({{0, 1}, {1, 1}}, PiecewiseLinear({{0, 1}, {1, 2}}));
  const TransferFunction b = with_emission({{0, 1}, {1, 1}}, PiecewiseLinear({{0, 1}, {1, 2.5}}));
  const std::array<ReferenceChannel, 2> channels{{{&a, 0.0}, {&b, 0.0}}};
  const Ray ray = make_ray(Vec3(0, 0, -3), Vec3(0, 0, 1));
  EXPECT_THROW(integrate_channels_reference(field, scene.box, channels, ray),
               std::invalid_argument);
  const std::array<ReferenceChannel, 2> same{{{&a, 0.0}, {&a, 1.0}}};
  EXPECT_NO_THROW(integrate_channels_reference(field, scene.box, same, ray));
}

}  // namespace
}  // namespace vrv::ray_accumulator_test
