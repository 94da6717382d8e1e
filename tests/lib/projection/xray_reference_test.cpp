// The X-ray reference against closed forms: a ramp's line, a grid sampled from a ramp (trilinear
// reproduces it: 1024 cells along the ray), a transfer function's extinction of a ramp (a
// piecewise-linear integrand with a jump), far origins, misses and corner chords.  The mpmath
// truths of tests/lib/projection_adversarial/ cover the rest.
#include "lib/projection/xray_reference.h"

#include <gtest/gtest.h>

#include <cmath>

#include "analytic/linear_ramp.h"
#include "analytic/marschner_lobb.h"
#include "lib/grid_field.h"

namespace vrv {
namespace {

TransferFunction jump_tf() {
  const PiecewiseLinear tau({{0.0, 0.0}, {0.3, 1.0}, {0.5, 0.2}, {0.5, 0.8}, {1.0, 0.5}});
  return TransferFunction::emission_extinction(tau, tau);
}

void expect_honest(const ProjectionResult& r, double truth, double tol) {
  EXPECT_TRUE(r.hit);
  EXPECT_LE(std::abs(r.value - truth), r.error_estimate) << "value " << r.value << " truth " << truth;
  EXPECT_LE(r.error_estimate, tol);
  EXPECT_TRUE(r.tolerance_met);
}

TEST(XrayReference, RampIsItsLineIntegral) {
  const LinearRamp ramp{{0.3, -0.2, 0.7}, 0.1};
  const Ray ray = make_ray({-2, 0.1, -0.3}, {1, 0.05, 0.2});
  const Box box;
  const ProjectionResult r = xray_reference(ramp, box, ray, {1e-13});
  // f at entry and exit, the integral of a line is its mean times the length.
  const double f0 = ramp.value(ray.at(r.t_entry)), f1 = ramp.value(ray.at(r.t_exit));
  expect_honest(r, 0.5 * (f0 + f1) * (r.t_exit - r.t_entry), 1e-13);
  EXPECT_EQ(r.evaluations, 2);
  EXPECT_TRUE(std::isnan(r.position));
}

TEST(XrayReference, GridOf1024CellsFromARamp) {
  const Box box{{-1, -1, -1}, {1, 1, 1}};
  const LinearRamp ramp{{0.25, 0.5, -0.125}, 0.5};
  const GridField grid(box, {1025, 2, 2}, GridLayout::node, Interpolation::trilinear,
                       [&](const Vec3& p) { return ramp.value(p); });
  const Ray ray = make_ray({-2, 0.1, 0.2}, {1, 0.01, -0.02});
  const ProjectionResult r = xray_reference(grid, box, ray, {1e-12});
  const double f0 = ramp.value(ray.at(r.t_entry)), f1 = ramp.value(ray.at(r.t_exit));
  expect_honest(r, 0.5 * (f0 + f1) * (r.t_exit - r.t_entry), 1e-12);
  EXPECT_EQ(r.evaluations, 4 * 1024);
  EXPECT_LT(r.error_estimate, 1e-13);  // rounding only: not absurd
}

TEST(XrayReference, ClassifiedRampIsTheAreaUnderTheTransferFunction) {
  // f runs from 0 to 1 along x over [-1, 1] (s = 2 f): int tau(f(s)) ds = 2 int_0^1 tau(v) dv.
  const LinearRamp ramp{{0.5, 0, 0}, 0.5};
  const TransferFunction tf = jump_tf();
  const Ray ray = make_ray({-3, 0.2, 0.1}, {1, 0, 0});
  const ProjectionResult r = xray_reference(ramp, Box{}, ray, {1e-13}, &tf);
  const double area = 0.5 * 0.3 * 1.0 + 0.5 * (1.0 + 0.2) * 0.2 + 0.5 * (0.8 + 0.5) * 0.5;
  expect_honest(r, 2 * area, 1e-13);
}

TEST(XrayReference, MissCornerAndFarOrigin) {
  const MarschnerLobb ml;
  const ProjectionResult miss = xray_reference(ml, Box{}, make_ray({-3, 1.5, 0}, {1, 0, 0}), {});
  EXPECT_FALSE(miss.hit);
  EXPECT_EQ(miss.value, 0.0);
  EXPECT_EQ(miss.evaluations, 0);
  // A chord of length 0 through a corner: nothing to integrate, exactly.
  const ProjectionResult corner = xray_reference(ml, Box{}, make_ray({0, 2, 1}, {1, -1, 0}), {});
  EXPECT_TRUE(corner.hit);
  EXPECT_EQ(corner.t_entry, corner.t_exit);
  EXPECT_EQ(corner.value, 0.0);
  // A ramp from 1e6 away: the origin's rounding (an ulp of 1e6, 1.2e-10) moves the line, so the
  // chord is the near one's to about that (the mpmath suite checks far origins exactly).
  const LinearRamp ramp{{0.2, -0.7, 0.4}, 0.3};
  const Vec3 d(1, 0.31, -0.17), p(0.1, -0.2, 0.05);
  const ProjectionResult near = xray_reference(ramp, Box{}, make_ray(p - 3 * d, d), {1e-12});
  const ProjectionResult far = xray_reference(ramp, Box{}, make_ray(p - 1e6 * d, d), {1e-12});
  EXPECT_LE(std::abs(far.value - near.value), 1e-9);
  EXPECT_TRUE(far.tolerance_met);
}

// The classified X-ray is the optical depth, which the emission-absorption reference carries by
// its own route (its accumulator, not these panels' sums): the two agree.
TEST(XrayReference, ClassifiedIsTheEmissionAbsorptionOpticalDepth) {
  const MarschnerLobb ml;
  const TransferFunction tf = TransferFunction::emission_extinction(PiecewiseLinear({{0, 0}, {1, 1}}),
                                                                    PiecewiseLinear({{0, 0}, {0.4, 1.0}, {1, 0.5}}));
  for (const Ray& ray : {make_ray({-3, 0.5, 0}, {1, 0, 0}), make_ray({-2, -1.5, 1.2}, {1, 0.8, -0.4})}) {
    const ProjectionResult x = xray_reference(ml, Box{}, ray, {1e-12}, &tf);
    ReferenceOptions ea;
    ea.stop_when_opaque = false;
    const ReferenceResult r = integrate_reference(ml, Box{}, tf, 0.0, ray, ea);
    EXPECT_TRUE(x.tolerance_met);
    EXPECT_NEAR(x.value, r.optical_depth, 1e-12);
  }
}

TEST(XrayReference, MarschnerLobbMeetsTheTolerance) {
  const MarschnerLobb ml;
  const Ray ray = make_ray({-3, 0.3, 0.2}, {1, 0.1, 0.05});
  const ProjectionResult tight = xray_reference(ml, Box{}, ray, {1e-12});
  const ProjectionResult loose = xray_reference(ml, Box{}, ray, {1e-6});
  EXPECT_TRUE(tight.tolerance_met);
  EXPECT_TRUE(loose.tolerance_met);
  EXPECT_LE(std::abs(tight.value - loose.value), loose.error_estimate + tight.error_estimate);
  EXPECT_LT(loose.evaluations, tight.evaluations);
}

}  // namespace
}  // namespace vrv
