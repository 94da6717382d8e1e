// Discrete projections against the references: the sums each rule makes, exactness where theory
// says so (a maximum exactly at a sample, a plateau once sampled, the trapezoid on a ramp), and
// the observed orders under step refinement (lib/order_estimate): MIP at a smooth interior
// maximum 2 (a sample misses the peak by O(h) in position, O(h^2) in value), at a kink of a grid's
// interpolant 1; X-ray by riemann at midpoints (the partial strategy) 2, trapezoid 2, Simpson 4.
#include "lib/projection/discrete_projection.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>
#include <vector>

#include "analytic/linear_ramp.h"
#include "analytic/marschner_lobb.h"
#include "lib/grid_field.h"
#include "lib/order_estimate.h"
#include "lib/projection/projection_reference.h"

namespace vrv {
namespace {

DiscreteProjectionConfig config(ProjectionMode mode, Strategy s, double step, XrayRule rule = XrayRule::trapezoid) {
  DiscreteProjectionConfig c;
  c.mode = mode;
  c.sampling.strategy = s;
  c.sampling.step = step;
  c.rule = rule;
  return c;
}

TEST(XrayRuleNames, RoundTrip) {
  for (auto r : {XrayRule::riemann, XrayRule::trapezoid, XrayRule::simpson}) EXPECT_EQ(parse_xray_rule(xray_rule_name(r)), r);
  EXPECT_FALSE(parse_xray_rule("alpha"));
}

TEST(DiscreteProjection, SumsOfARampAlongX) {
  // f = x along x from -1 to 1, step 0.5 (samples at -0.75, -0.25, 0.25, 0.75).
  const LinearRamp ramp{{1, 0, 0}, 0};
  const TransferFunction tf;
  const Ray ray = make_ray({-2, 0, 0}, {1, 0, 0});
  const auto run = [&](ProjectionMode m, XrayRule r) {
    return discrete_projection(ramp, Box{}, tf, ray, config(m, Strategy::step, 0.5, r));
  };
  const auto mip = run(ProjectionMode::mip, XrayRule::trapezoid);
  EXPECT_EQ(mip.value, 0.75);
  EXPECT_EQ(mip.position, 2.75);
  EXPECT_EQ(mip.samples, 4);
  EXPECT_NEAR(run(ProjectionMode::xray, XrayRule::riemann).value, 0.0, 1e-15);
  EXPECT_NEAR(run(ProjectionMode::xray, XrayRule::trapezoid).value, 0.0, 1e-15);
  EXPECT_EQ(run(ProjectionMode::xray, XrayRule::trapezoid).samples, 6);  // entry, 4 samples, exit
  EXPECT_EQ(run(ProjectionMode::xray, XrayRule::simpson).samples, 11);   // and 5 midpoints
  // A miss: nothing sampled.
  const auto miss = discrete_projection(ramp, Box{}, tf, make_ray({-2, 3, 0}, {1, 0, 0}), config(ProjectionMode::mip, Strategy::step, 0.5));
  EXPECT_EQ(miss.samples, 0);
  EXPECT_EQ(miss.value, 0.0);
  EXPECT_TRUE(std::isnan(miss.position));
}

TEST(DiscreteProjection, MaximumExactlyAtASampleAndAPlateauAreExact) {
  // A node peak at x = 0.25 on the line y = z = 0; vtk's samples sit at whole steps from the entry.
  const Box box;
  const GridField grid(box, {9, 3, 3}, GridLayout::node, Interpolation::trilinear, [](const Vec3& p) {
    return std::abs(p.x() - 0.25) < 1e-9 && std::abs(p.y()) < 1e-9 && std::abs(p.z()) < 1e-9 ? 1.0 : 0.1;
  });
  const TransferFunction tf;
  const Ray ray = make_ray({-2, 0, 0}, {1, 0, 0});
  const ProjectionResult ref = projection_reference(grid, box, tf, ray, ProjectionMode::mip, {});
  EXPECT_EQ(ref.value, 1.0);
  EXPECT_EQ(ref.position, 2.25);
  for (double h : {0.25, 0.125, 0.0625}) {
    const auto d = discrete_projection(grid, box, tf, ray, config(ProjectionMode::mip, Strategy::vtk, h));
    EXPECT_EQ(d.value, ref.value) << h;
    EXPECT_EQ(d.position, ref.position) << h;
  }
  // The same kink between samples (step's midpoints): first order, the slope (0.9 / 0.25) times
  // the distance to the nearest sample, at most h / 2 (steps chosen never to hit x = 0.25).
  for (double h : {0.07, 0.035, 0.0175, 0.00875}) {
    const auto d = discrete_projection(grid, box, tf, ray, config(ProjectionMode::mip, Strategy::step, h));
    EXPECT_GT(ref.value - d.value, 0) << h;
    EXPECT_LE(ref.value - d.value, 3.6 * h / 2 * (1 + 1e-12)) << h;
  }
  // A plateau: any sample on it is exact.
  const LinearRamp flat{{0, 0.4, 0}, 0.2};
  const auto d = discrete_projection(flat, box, tf, make_ray({-2, 0.3, 0.1}, {1, 0, 0}), config(ProjectionMode::mip, Strategy::step, 0.3));
  EXPECT_EQ(d.value, flat.value({0, 0.3, 0.1}));
}

// Mean |discrete - reference| over rays through a smooth Marschner-Lobb at halving steps.
double observed_order(ProjectionMode mode, Strategy strategy, XrayRule rule, std::vector<double> steps) {
  const MarschnerLobb ml{2, 0.5};
  const TransferFunction tf;
  std::mt19937 rng(26);
  std::uniform_real_distribution<double> u(-0.7, 0.7);
  std::vector<Ray> rays;
  for (int i = 0; i < 24; ++i) rays.push_back(make_ray({-3, u(rng), u(rng)}, {1, 0.3 * u(rng), 0.3 * u(rng)}));
  std::vector<double> errors;
  for (double h : steps) {
    double sum = 0;
    for (const Ray& ray : rays) {
      const ProjectionResult ref = projection_reference(ml, Box{}, tf, ray, mode, {1e-13});
      const auto d = discrete_projection(ml, Box{}, tf, ray, config(mode, strategy, h, rule));
      sum += std::abs(d.value - ref.value);
    }
    errors.push_back(sum / rays.size());
  }
  const double order = estimate_order(steps, errors).order;
  std::cout << projection_mode_name(mode) << " " << strategy_name(strategy) << " " << xray_rule_name(rule)
            << ": mean errors";
  for (double e : errors) std::cout << " " << e;
  std::cout << ", observed order " << order << "\n";
  return order;
}

TEST(DiscreteProjectionOrders, MipAtASmoothInteriorMaximumIsSecondOrder) {
  EXPECT_NEAR(observed_order(ProjectionMode::mip, Strategy::step, XrayRule::trapezoid, {0.02, 0.01, 0.005, 0.0025}), 2.0, 0.25);
}

TEST(DiscreteProjectionOrders, XrayRules) {
  const std::vector<double> steps{0.08, 0.04, 0.02, 0.01};
  EXPECT_NEAR(observed_order(ProjectionMode::xray, Strategy::partial, XrayRule::riemann, steps), 2.0, 0.15);
  EXPECT_NEAR(observed_order(ProjectionMode::xray, Strategy::step, XrayRule::trapezoid, steps), 2.0, 0.15);
  EXPECT_NEAR(observed_order(ProjectionMode::xray, Strategy::step, XrayRule::simpson, steps), 4.0, 0.3);
  // Riemann with `step` keeps the last sample's whole step past the exit: first order.
  EXPECT_NEAR(observed_order(ProjectionMode::xray, Strategy::step, XrayRule::riemann, steps), 1.0, 0.3);
}

}  // namespace
}  // namespace vrv
