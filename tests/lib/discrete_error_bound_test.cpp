// The a-priori bound of a discrete raycast (lib/discrete_error_bound.h) against the error measured
// with the reference: never below it, on smooth, kinked, jumping, thick, grid and ramp scenes,
// every supported rule and several placements; not absurdly above it; unavailable (and saying
// why) for what it does not cover.
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "lib/discrete_error_bound.h"
#include "lib/discrete_error_estimate.h"
#include "tests/lib/discrete_error_scenes.h"
#include "lib/reference_integrator.h"
#include "lib/vrv.h"

namespace vrv::discrete_error_bound_test {

using discrete_error_scenes::Case;
using discrete_error_scenes::cases;
using discrete_error_scenes::config;
using discrete_error_scenes::scene_text;

std::vector<Ray> rays() { return discrete_error_scenes::rays(40, 29); }

struct Measured {
  double error = 0, bound = 0;
};

// Every ray: the error (against the reference, its own estimate added to
// the bound, since the measured error is only known to within it) and the bound.
std::vector<Measured> measure(const Scene& scene, const DiscreteConfig& c) {
  std::vector<Measured> out;
  for (const Ray& ray : rays()) {
    const ReferenceResult ref = integrate_reference(scene, ray, {1e-13});
    const DiscreteResult d = discrete_raycast(scene, ray, c);
    const DiscreteErrorBound b = discrete_error_bound(scene, ray, c);
    EXPECT_TRUE(b.available()) << b.unavailable;
    out.push_back({std::abs(d.value - ref.value), b.bound + ref.error_estimate});
  }
  return out;
}

// A bound adds every segment's error in absolute value, where the error of a smooth ray cancels
// between segments (the interpolation errors of an oscillating g(f) change sign).  The largest
// median measured over these cases is 143 (the grid, trapezoid, vtk placement); single rays reach
// a few thousand where their error happens to cancel.
constexpr double kMedianLooseness = 500;

TEST(DiscreteErrorBound, NeverBelowTheMeasuredError) {
  const SegmentRule rules[] = {SegmentRule::riemann, SegmentRule::alpha, SegmentRule::trapezoid,
                               SegmentRule::exact_linear};
  struct Placement {
    Strategy strategy;
    double value;
  };
  const Placement placements[] = {{Strategy::step, 0.05}, {Strategy::step, 0.005}, {Strategy::entry_exit_corner, 1},
                                  {Strategy::vtk, 0.02}, {Strategy::eye, 2}};
  for (const Case& k : cases()) {
    const Scene scene = parse_scene(k.text, k.name + ".toml");
    for (SegmentRule rule : rules)
      for (const Placement& p : placements) {
        const DiscreteConfig c = config(rule, p.strategy, p.value);
        std::vector<double> ratios;
        for (const Measured& m : measure(scene, c)) {
          EXPECT_LE(m.error, m.bound) << k.name << " " << segment_rule_name(rule) << " "
                                      << strategy_name(p.strategy) << " " << p.value;
          if (m.error > 1e-12) ratios.push_back(m.bound / m.error);
        }
        // Not absurdly above: the median ray within kMedianLooseness of its error (docs/error-bounds.md).
        ASSERT_GE(ratios.size(), 20u) << k.name;
        std::sort(ratios.begin(), ratios.end());
        const double median = ratios[ratios.size() / 2];
        EXPECT_LE(median, kMedianLooseness) << k.name << " " << segment_rule_name(rule) << " "
                                            << strategy_name(p.strategy) << " " << p.value;
        fmt::print("{:12} {:13} {:18} {:6} rays {:3} median bound/error {:9.3g}\n", k.name,
                   segment_rule_name(rule), strategy_name(p.strategy), p.value, ratios.size(), median);
      }
  }
}

// Where g(f) and tau(f) only kink (no jump), the bound falls at the rule's order once the steps are
// shorter than the field's features: the second-order rules' by ~100 for a step 10 times smaller,
// riemann's by at least 10 (first order: its E = g dx against the exact (1 - e^-tau dx) / tau;
// measured 32 here, where the kinks' second-order terms still weigh).
TEST(DiscreteErrorBound, FallsAtTheRulesOrder) {
  const Scene scene = parse_scene(cases()[0].text, "ml_kinked.toml");
  const Ray ray = make_ray(Vec3(-3, 0.1, 0.2), Vec3(1, 0.05, 0.02));
  const auto ratio = [&](SegmentRule rule) {
    return discrete_error_bound(scene, ray, config(rule, Strategy::step, 0.002)).bound /
           discrete_error_bound(scene, ray, config(rule, Strategy::step, 0.0002)).bound;
  };
  for (SegmentRule rule : {SegmentRule::alpha, SegmentRule::trapezoid, SegmentRule::exact_linear}) {
    EXPECT_GT(ratio(rule), 50) << segment_rule_name(rule);
    EXPECT_LT(ratio(rule), 200) << segment_rule_name(rule);
  }
  EXPECT_GT(ratio(SegmentRule::riemann), 10);
  EXPECT_LT(ratio(SegmentRule::riemann), 100);
}

// Outside what it covers, no number: the reason instead (never a bound that does not hold).
TEST(DiscreteErrorBound, SaysWhyNoBoundIsDerived) {
  const Scene scene = parse_scene(cases()[0].text, "ml_kinked.toml");
  const Ray ray = make_ray(Vec3(-3, 0.1, 0.2), Vec3(1, 0, 0));
  const DiscreteConfig partial = config(SegmentRule::riemann, Strategy::partial, 0.01);
  const DiscreteErrorBound b = discrete_error_bound(scene, ray, partial);
  EXPECT_EQ(b.bound, 0);
  EXPECT_NE(b.unavailable.find("partial"), std::string::npos);
  const Scene opacity = parse_scene(scene_text("kind = \"marschner_lobb\"",
                                               "opacity = [[0.0, 0.0], [1.0, 0.5]]\ncolor = [[0.0, 1.0], [1.0, 1.0]]"),
                                    "opacity.toml");
  EXPECT_NE(discrete_error_bound(opacity, ray, config(SegmentRule::alpha, Strategy::step, 0.01)).unavailable.find("opacity"),
            std::string::npos);
}

// What the segment analysis leaves out (corrections, oversampling, tables, float, termination,
// skipping, pre-classification, moreland) is the exact difference from the nearest analysed
// configuration: the bound holds on every scene, and the estimate misses by what the analysed
// configuration's does.
TEST(DiscreteErrorBound, CoversEveryConfigurationThroughItsAnalysedOne) {
  struct Variant {
    const char* name;
    DiscreteConfig config;
  };
  std::vector<Variant> variants;
  const auto add = [&](const char* name, SegmentRule rule, auto&& change) {
    DiscreteConfig c = config(rule, Strategy::step, 0.02);
    change(c);
    EXPECT_FALSE(outside_segment_analysis(c).empty()) << name;
    variants.push_back({name, c});
  };
  add("oversample 4, lacroute", SegmentRule::alpha, [](DiscreteConfig& c) { c.oversample = 4, c.correction = Correction::lacroute; });
  add("oversample 4, lee_newman, centred", SegmentRule::alpha, [](DiscreteConfig& c) {
    c.oversample = 4, c.correction = Correction::lee_newman, c.centred_oversamples = true;
  });
  add("oversample 3, none", SegmentRule::riemann, [](DiscreteConfig& c) { c.oversample = 3; });
  add("termination 0.9", SegmentRule::trapezoid, [](DiscreteConfig& c) { c.termination = 0.9; });
  add("skip 0.01", SegmentRule::alpha, [](DiscreteConfig& c) { c.skip_below = 0.01; });
  add("float", SegmentRule::exact_linear, [](DiscreteConfig& c) { c.precision = Precision::single_precision; });
  add("tables 256", SegmentRule::alpha, [](DiscreteConfig& c) { c.table_size = 256; });
  add("pre-classification", SegmentRule::trapezoid, [](DiscreteConfig& c) { c.classification = Classification::pre; });
  add("moreland", SegmentRule::moreland, [](DiscreteConfig&) {});
  for (const Case& k : cases()) {
    const Scene scene = parse_scene(k.text, k.name + ".toml");
    const bool grid = std::holds_alternative<GridField>(scene.field);
    for (const Variant& v : variants) {
      if (v.config.classification == Classification::pre && !grid) continue;  // a grid option
      const DiscreteConfig base = analysed_configuration(v.config);
      EXPECT_TRUE(outside_segment_analysis(base).empty()) << v.name;
      for (const Ray& ray : rays()) {
        const ReferenceResult ref = integrate_reference(scene, ray, {1e-13});
        const double value = discrete_raycast(scene, ray, v.config).value;
        const DiscreteErrorBound b = discrete_error_bound(scene, ray, v.config);
        ASSERT_TRUE(b.available()) << b.unavailable;
        EXPECT_LE(std::abs(value - ref.value), b.bound + ref.error_estimate) << k.name << " " << v.name;
        const DiscreteErrorEstimate e = estimate_discrete_error(scene, ray, v.config);
        const DiscreteErrorEstimate own = estimate_discrete_error(scene, ray, base);
        const double base_miss = std::abs(own.error - (discrete_raycast(scene, ray, base).value - ref.value));
        EXPECT_NEAR(e.error, value - ref.value, base_miss + 1e-12 * (1 + std::abs(value))) << k.name << " " << v.name;
        EXPECT_EQ(e.cast_difference, b.cast_difference);
      }
    }
  }
}

// Hard rays: from far away (the sample points round by ulps of the origin's size), along a box edge,
// through a corner, and at a step of 1e-4 (20,000 segments); the bound still holds.
TEST(DiscreteErrorBound, HoldsOnHardRays) {
  const Ray hard[] = {make_ray(Vec3(-1e7, 0.1, 0.2), Vec3(1, 0, 0)), make_ray(Vec3(0.3, -3e5, 0.1), Vec3(0.01, 1, 0.02)),
                      make_ray(Vec3(-2, 1, 1), Vec3(1, 0, 0)), make_ray(Vec3(-2, 0.999, -3), Vec3(1, 0, 1))};
  for (const Case& k : cases()) {
    const Scene scene = parse_scene(k.text, k.name + ".toml");
    for (const Ray& ray : hard)
      for (SegmentRule rule : {SegmentRule::alpha, SegmentRule::exact_linear})
        for (double step : {0.01, 1e-4}) {
          const DiscreteConfig c = config(rule, Strategy::step, step);
          const ReferenceResult ref = integrate_reference(scene, ray, {1e-13});
          const DiscreteErrorBound b = discrete_error_bound(scene, ray, c);
          ASSERT_TRUE(b.available()) << b.unavailable;
          EXPECT_LE(std::abs(discrete_raycast(scene, ray, c).value - ref.value), b.bound + ref.error_estimate)
              << k.name << " " << segment_rule_name(rule) << " " << step << " origin " << ray.origin.transpose();
        }
  }
}

// Where g and tau are constant the Riemann rule's error is its first-order term alone, which the
// bound computes exactly: only the rounding charges separate them, and they must cover every
// rounding of the raycast.  The error-prediction study found the segments' rounded ends missing
// from them (results/error-prediction: 5 rays of 26,880 a few 1e-14 below, at 87 segments).
TEST(DiscreteErrorBound, ExactTermsLeaveOnlyRounding) {
  const Scene scene = parse_scene(scene_text("kind = \"marschner_lobb\"",
                                             "emission = [[0.0, 1.0], [1.0, 1.0]]\nextinction = [[0.0, 2.0], [1.0, 2.0]]"),
                                  "constant.toml");
  std::vector<Ray> all = discrete_error_scenes::rays(30, 7);
  for (double far : {1e3, 1e6}) all.push_back(make_ray(Vec3(-far, 0.3, -0.2), Vec3(1, 1e-3, 2e-3)));
  for (SegmentRule rule : {SegmentRule::riemann, SegmentRule::alpha})
    for (double step : {0.005, 0.0025, 0.001})
      for (const Ray& ray : all) {
        const DiscreteConfig c = config(rule, Strategy::step, step);
        const ReferenceResult ref = integrate_reference(scene, ray, {1e-13});
        const double error = std::abs(discrete_raycast(scene, ray, c).value - ref.value);
        const DiscreteErrorBound b = discrete_error_bound(scene, ray, c);
        const std::string what = fmt::format("{} {} origin {}", segment_rule_name(rule), step, ray.origin.norm());
        EXPECT_LE(error, b.bound + ref.error_estimate) << what;
        EXPECT_LE(b.bound, 10 * error + 1e-10) << what;  // the ends of the range aside, tight
      }
}

// Optically thick segments the steps do not resolve compound their depth errors (e^D_k reached 1e14
// on the error-prediction study's thick scene at step 0.2); I and I_h are both >= 0, so the bound
// is never more than the larger of them (I from above through the segments' ranges).
TEST(DiscreteErrorBound, NeverAboveTheLightItself) {
  const Scene scene = parse_scene(scene_text("kind = \"marschner_lobb\"", discrete_error_scenes::kinked(100)), "thick.toml");
  double worst = 0;
  for (SegmentRule rule : {SegmentRule::riemann, SegmentRule::alpha, SegmentRule::trapezoid, SegmentRule::exact_linear})
    for (double step : {0.2, 0.1})
      for (const Ray& ray : rays()) {
        const DiscreteConfig c = config(rule, Strategy::step, step);
        const ReferenceResult ref = integrate_reference(scene, ray, {1e-13});
        const double value = discrete_raycast(scene, ray, c).value;
        const DiscreteErrorBound b = discrete_error_bound(scene, ray, c);
        EXPECT_LE(std::abs(value - ref.value), b.bound + ref.error_estimate);
        worst = std::max(worst, b.bound / std::max({ref.value, value, 1e-300}));
      }
  // Measured 34 (the upper bound on I takes g's largest and tau's smallest value over each
  // segment of 0.2); without the cap, bounds of 1e14 on these rays.
  fmt::print("largest bound / max(I, I_h): {:.3g}\n", worst);
  EXPECT_LE(worst, 100);
}

// g = kappa tau: alpha and exact_linear composite kappa (1 - e^-dPhi) per segment, so only the depth's
// error counts; on a ramp, whose tau is linear along the ray, the centred samples integrate it
// exactly and the bound is the compositing's rounding (4 ulps per segment, 2,000 segments).
TEST(DiscreteErrorBound, ProportionalTransferFunctionsNeedOnlyTheDepth) {
  // f runs from 0.2 to 0.8 along the ray: no breakpoint of the transfer function on it.
  const Scene scene = parse_scene(scene_text("kind = \"linear_ramp\"\ngradient = [0.3, 0.0, 0.0]\noffset = 0.5",
                                             "emission = [[0.0, 0.0], [1.0, 1.0]]\nextinction = [[0.0, 0.0], [1.0, 0.5]]",
                                             0.3),
                                  "ramp.toml");
  const Ray ray = make_ray(Vec3(-3, 0.1, 0.2), Vec3(1, 0, 0));
  const ReferenceResult ref = integrate_reference(scene, ray, {1e-13});
  for (SegmentRule rule : {SegmentRule::alpha, SegmentRule::exact_linear}) {
    const DiscreteConfig c = config(rule, Strategy::step, 1e-3);
    const DiscreteErrorBound b = discrete_error_bound(scene, ray, c);
    EXPECT_LE(std::abs(discrete_raycast(scene, ray, c).value - ref.value), b.bound + ref.error_estimate);
    EXPECT_LT(b.bound, 1e-11) << segment_rule_name(rule);
  }
  // trapezoid's emission is not kappa (1 - e^-dPhi): the general bound, second order.
  const DiscreteErrorBound trapezoid = discrete_error_bound(scene, ray, config(SegmentRule::trapezoid, Strategy::step, 1e-3));
  EXPECT_GT(trapezoid.bound, 1e-9);
  EXPECT_LT(trapezoid.bound, 1e-5);
}

// A ray that misses the box: the raycast returns the background exactly.
TEST(DiscreteErrorBound, AMissIsExact) {
  const Scene scene = parse_scene(cases()[3].text, "ml_jump.toml");
  const DiscreteErrorBound b =
      discrete_error_bound(scene, make_ray(Vec3(-3, 5, 0), Vec3(1, 0, 0)), config(SegmentRule::alpha, Strategy::step, 0.01));
  EXPECT_TRUE(b.available());
  EXPECT_EQ(b.bound, 0);
}

}  // namespace vrv::discrete_error_bound_test
