// The MIP reference on cases with known answers: a ramp (the maximum at the exit face), a grid
// cell's cubic (its interior maximum in closed form), a plateau (its start), classified maxima
// (the extinction's maximum, which is not the extinction of the maximum), a miss, and the two
// candidate routines.  The mpmath truths of tests/lib/projection_adversarial/ cover the rest.
#include "lib/projection/mip_reference.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "analytic/linear_ramp.h"
#include "analytic/marschner_lobb.h"
#include "lib/grid_field.h"

namespace vrv {
namespace {

TransferFunction hump_tf() {
  const PiecewiseLinear tau({{0.0, 0.0}, {0.3, 1.0}, {0.5, 0.2}, {0.5, 0.8}, {1.0, 0.5}});
  return TransferFunction::emission_extinction(tau, tau);
}

TEST(MipReference, RampPeaksAtTheExitFace) {
  const LinearRamp ramp{{0.5, 0, 0}, 0.5};
  const ProjectionResult r = mip_reference(ramp, Box{}, make_ray({-3, 0.2, 0.1}, {1, 0, 0}), {});
  EXPECT_EQ(r.value, 1.0);
  EXPECT_EQ(r.position, 4.0);
  EXPECT_LE(r.error_estimate, 1e-14);  // the ramp's rounding (4 eps) times the Lebesgue factor
  EXPECT_FALSE(r.ambiguous);
}

TEST(MipReference, ClassifiedIsTheMaximumOfTheExtinctionNotItsValueAtTheMaximum) {
  const LinearRamp ramp{{0.5, 0, 0}, 0.5};  // f = s / 2 along the ray from the entry
  const TransferFunction tf = hump_tf();
  const ProjectionResult r = mip_reference(ramp, Box{}, make_ray({-3, 0.2, 0.1}, {1, 0, 0}), {1e-13}, &tf);
  EXPECT_NEAR(r.value, 1.0, r.error_estimate);  // tau's peak at f = 0.3 ...
  EXPECT_LE(r.error_estimate, 1e-13);
  EXPECT_NEAR(r.position, 2 + 0.6, 1e-12);          // ... reached at s = 0.6
  EXPECT_EQ(tf.extinction(1.0), 0.5);               // not tau(max f)
}

TEST(MipReference, ClassifiedJumpIsReachedFromBothSides) {
  // f falls from 0.7 to 0.45 across the jump at 0.5: the sup is the larger side, 0.8 at f = 0.5+.
  const LinearRamp ramp{{-0.125, 0, 0}, 0.575};
  const TransferFunction tf = hump_tf();
  const ProjectionResult r = mip_reference(ramp, Box{}, make_ray({-3, 0, 0}, {1, 0, 0}), {1e-13}, &tf);
  EXPECT_NEAR(r.value, 0.8, r.error_estimate);
  EXPECT_NEAR(r.position, 2 + 1.6, 1e-12);  // f = 0.5 at x = 0.6
}

TEST(MipReference, CubicCellMaximumInClosedForm) {
  // One trilinear cell whose cubic along a diagonal has an interior maximum; the truth by
  // golden-section on the interpolant itself to 1e-15.
  const Box box;
  const GridField grid(box, {2, 2, 2}, GridLayout::node, Interpolation::trilinear, [](const Vec3& p) {
    return 0.1 + 0.9 * (p.x() > 0) * (p.y() < 0) + 0.7 * (p.z() > 0) * (p.x() < 0) + 0.3 * (p.y() > 0);
  });
  const Ray ray = make_ray({-1.5, -1.2, -1.4}, {1, 0.8, 0.9});
  const ProjectionResult r = mip_reference(grid, box, ray, {1e-13});
  double a = r.t_entry, b = r.t_exit;
  const double g = (std::sqrt(5.0) - 1) / 2;
  const auto f = [&](double t) { return grid.value(ray.at(t)); };
  for (int i = 0; i < 200; ++i) {
    const double c = b - g * (b - a), d = a + g * (b - a);
    (f(c) > f(d) ? b : a) = (f(c) > f(d) ? d : c);
  }
  const double truth = std::max({f(0.5 * (a + b)), f(r.t_entry), f(r.t_exit)});
  EXPECT_LE(std::abs(r.value - truth), r.error_estimate + 1e-15);
  EXPECT_LE(r.error_estimate, 1e-14);
  EXPECT_GT(r.position, r.t_entry);
  EXPECT_LT(r.position, r.t_exit);
}

// The same cell scaled by 2^-700 and 2^700: scaling by a power of two is exact in every value, so
// the maximum is the unscaled one's, scaled, bit for bit.  The derivative's discriminant B^2 - 4AC
// underflowed near 1e-200 (and overflowed near 1e200): the interior maximum was missed, 6.5e-3
// off relative with an estimate of 1e-214 (a helper's honesty hunt).
TEST(MipReference, CubicCellMaximumAtAnyScale) {
  const Box box;
  const auto cell = [&](double scale) {
    return GridField(box, {2, 2, 2}, GridLayout::node, Interpolation::trilinear, [scale](const Vec3& p) {
      return scale * (0.1 + 0.9 * (p.x() > 0) * (p.y() < 0) + 0.7 * (p.z() > 0) * (p.x() < 0) + 0.3 * (p.y() > 0));
    });
  };
  const Ray ray = make_ray({-1.5, -1.2, -1.4}, {1, 0.8, 0.9});
  const ProjectionResult one = mip_reference(cell(1), box, ray, {1e-13});
  ASSERT_GT(one.position, one.t_entry);  // an interior maximum
  for (const int e : {-700, 700}) {
    const double scale = std::ldexp(1.0, e);
    const ProjectionResult r = mip_reference(cell(scale), box, ray, {1e-13 * scale});
    EXPECT_EQ(r.value, std::ldexp(one.value, e)) << e;
    EXPECT_EQ(r.position, one.position) << e;
    EXPECT_LE(r.error_estimate, 2 * std::ldexp(one.error_estimate, e)) << e;
  }
}

// Two node peaks along a node line (f piecewise linear there, its maxima the node values): a gap
// well above the estimate is told apart; one within the field's rounding is a tie (the first).
TEST(MipReference, TwoPeaksToldApartOrFlagged) {
  const Box box;
  const auto peaks = [&](double first, double second) {
    return GridField(box, {9, 3, 3}, GridLayout::node, Interpolation::trilinear, [=](const Vec3& p) {
      const bool line = std::abs(p.y()) < 1e-9 && std::abs(p.z()) < 1e-9;
      return !line ? 0.2 : std::abs(p.x() + 0.5) < 1e-9 ? first : std::abs(p.x() - 0.5) < 1e-9 ? second : 0.3;
    });
  };
  const Ray ray = make_ray({-2, 0, 0}, {1, 0, 0});
  for (double gap : {1e-13, -1e-13}) {
    const GridField grid = peaks(0.9, 0.9 + gap);
    const ProjectionResult r = mip_reference(grid, box, ray, {1e-12});
    EXPECT_EQ(r.value, 0.9 + std::max(gap, 0.0));
    EXPECT_LT(2 * r.error_estimate, std::abs(gap));
    EXPECT_FALSE(r.ambiguous) << gap;
    EXPECT_EQ(r.position, gap > 0 ? 2.5 : 1.5);
  }
  const GridField close = peaks(0.9, std::nextafter(0.9, 1.0));
  const ProjectionResult r = mip_reference(close, box, ray, {1e-12});
  EXPECT_LE(std::abs(r.value - std::nextafter(0.9, 1.0)), r.error_estimate);
  EXPECT_EQ(r.position, 1.5);  // an ulp apart is a tie within the grid's rounding: the first
  const GridField tied = peaks(0.9, 0.9);
  EXPECT_EQ(mip_reference(tied, box, ray, {1e-12}).position, 1.5);  // an exact tie: the first
}

TEST(MipReference, PlateauReportsItsStart) {
  const LinearRamp flat{{0, 0.4, 0}, 0.2};  // constant along x
  const ProjectionResult r = mip_reference(flat, Box{}, make_ray({-2, 0.3, 0.1}, {1, 0, 0}), {});
  EXPECT_EQ(r.position, 1.0);
  EXPECT_FALSE(r.ambiguous);
}

TEST(MipReference, MarschnerLobbRefinedOnTheField) {
  // Along x at y = 0, z = 0.3 the radial term peaks wherever cos(pi |x| / 2) = k / 6 (13 peaks,
  // tied); a tilt of 1e-3 in z lowers each later one (sin(pi z / 2) grows): the value is the
  // field's own at the reported position, and no point of the chord exceeds value + estimate.
  const MarschnerLobb ml;
  const Ray ray = make_ray({-2, 0, 0.3}, {1, 0, 1e-3});
  const ProjectionResult r = mip_reference(ml, Box{}, ray, {1e-12});
  EXPECT_TRUE(r.tolerance_met);
  const double at = ml.value(ray.at(r.position));
  EXPECT_NEAR(at, r.value, 1e-15);
  // Every point of the chord is at most the value plus the estimate.
  for (int i = 0; i <= 20000; ++i) {
    const double t = r.t_entry + (r.t_exit - r.t_entry) * i / 20000;
    ASSERT_LE(ml.value(ray.at(t)), r.value + r.error_estimate) << t;
  }
}

TEST(MipReference, MissAndCorner) {
  const MarschnerLobb ml;
  const ProjectionResult miss = mip_reference(ml, Box{}, make_ray({-3, 1.5, 0}, {1, 0, 0}), {});
  EXPECT_FALSE(miss.hit);
  EXPECT_EQ(miss.value, 0.0);
  EXPECT_TRUE(std::isnan(miss.position));
  const ProjectionResult corner = mip_reference(ml, Box{}, make_ray({0, 2, 1}, {1, -1, 0}), {});
  EXPECT_TRUE(corner.hit);
  EXPECT_NEAR(corner.value, ml.value({1, 1, 1}), 1e-12);
  EXPECT_EQ(corner.t_entry, corner.t_exit);
}

TEST(ExtremumBreaks, QuadraticDerivativeRootsInClosedForm) {
  // p(x) = T3(x) = 4x^3 - 3x on [-1, 1]: p' = 12 x^2 - 3, roots +-1/2.
  RayPanel panel{-1, 1, {0, 0, 0, 1}, {}, 0, 0, true};
  std::vector<double> out;
  projection_detail::extremum_breaks(panel, out);
  ASSERT_EQ(out.size(), 4u);
  EXPECT_EQ(out[0], -1);
  EXPECT_NEAR(out[1], -0.5, 1e-15);
  EXPECT_NEAR(out[2], 0.5, 1e-15);
  EXPECT_EQ(out[3], 1);
  // A close pair: c1 = 3 - 1e-12 gives p' = 12 x^2 - 1e-12, roots +-2.9e-7, between any two of
  // the points a sampling of p' would use.
  RayPanel close{0, 2, {0, 3 - 1e-12, 0, 1}, {}, 0, 0, true};
  out.clear();
  projection_detail::extremum_breaks(close, out);
  ASSERT_EQ(out.size(), 4u);
  const double root = std::sqrt(1e-12 / 12);
  EXPECT_NEAR(out[1], 1 - root, 1e-3 * root);
  EXPECT_NEAR(out[2], 1 + root, 1e-3 * root);
}

}  // namespace
}  // namespace vrv
