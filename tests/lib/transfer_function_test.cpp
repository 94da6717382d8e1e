// The transfer-function classes as the exact integral sees them: (a) proportional, (b) general,
// (c) steps, (d) a narrow peak, (e) the opacity / colour convention -- their breakpoints, jumps and
// peak crossings -- on Marschner-Lobb, ray by ray against the independent long-double integral
// (reference_check.h); and where a transfer function is transparent (the empty-space search).
#include "lib/transfer_function.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "tests/lib/reference_check.h"

namespace vrv {
namespace {

using namespace reference_check;

TEST(ReferenceIntegratorMarschnerLobb, ProportionalTransfer) {
  check_rays("ML (a) proportional", kML, kMLRef, tf_proportional(), 0, random_rays(30, 1));
}

TEST(ReferenceIntegratorMarschnerLobb, GeneralTransfer) {
  check_rays("ML (b) general", kML, kMLRef, tf_general(), 0, random_rays(30, 2));
}

TEST(ReferenceIntegratorMarschnerLobb, StepTransfer) {
  check_rays("ML (c) step", kML, kMLRef, tf_step(), 0, random_rays(30, 3));
}

TEST(ReferenceIntegratorMarschnerLobb, NarrowPeakTransfer) {
  check_rays("ML (d) narrow peak", kML, kMLRef, tf_peak(), 0, random_rays(30, 4));
}

TEST(ReferenceIntegratorMarschnerLobb, OpacityColorTransfer) {
  check_rays("ML (e) opacity/color", kML, kMLRef, tf_opacity(), 0, random_rays(30, 5));
}

// A cell is empty only when the transfer function is zero on its whole node range.
TEST(TransferFunction, TransparentOnlyWhereBothCurvesAreZero) {
  const TransferFunction ee = TransferFunction::emission_extinction(
      curve({{0.0, 0.0}, {0.2, 0.0}, {1.0, 1.0}}), curve({{0.0, 0.0}, {0.3, 0.0}, {1.0, 2.0}}));
  EXPECT_TRUE(ee.transparent_on(-5, 0.2));
  EXPECT_FALSE(ee.transparent_on(-5, 0.2000001));  // emission rises past 0.2
  EXPECT_FALSE(ee.transparent_on(0.25, 0.26));     // extinction zero, emission not
  const TransferFunction jump = TransferFunction::emission_extinction(
      curve({{0.0, 0.0}, {0.5, 0.0}, {0.5, 1.0}}), curve({{0.0, 0.0}, {0.5, 0.0}, {0.5, 1.0}}));
  EXPECT_TRUE(jump.transparent_on(0.1, 0.4999999));
  EXPECT_FALSE(jump.transparent_on(0.1, 0.5));  // at the jump the value is the upper one
  const TransferFunction oc = TransferFunction::opacity_color(curve({{0.0, 0.0}, {0.4, 0.0}, {1.0, 0.5}}),
                                                              curve({{0.0, 1.0}, {1.0, 1.0}}), 1.0);
  EXPECT_TRUE(oc.transparent_on(0.0, 0.4));  // opacity 0: no extinction, so no light either
  EXPECT_FALSE(oc.transparent_on(0.0, 0.41));
}

// The gate before any empty-space search: transparent at some value of the range, including a
// zero stretch open at both ends (a jump down into it and a jump up out of it, no control point
// inside), one where only a midpoint of the range's ends is transparent, and a single value.
TEST(TransferFunction, TransparentSomewhereFindsEveryZeroStretch) {
  const TransferFunction ee = TransferFunction::emission_extinction(
      curve({{0.0, 0.0}, {0.2, 0.0}, {1.0, 1.0}}), curve({{0.0, 0.0}, {0.3, 0.0}, {1.0, 2.0}}));
  EXPECT_TRUE(ee.transparent_somewhere(0.1, 5));
  EXPECT_TRUE(ee.transparent_somewhere(-3, -2));   // below the first point: constant 0
  EXPECT_FALSE(ee.transparent_somewhere(0.2000001, 5));
  EXPECT_TRUE(ee.transparent_somewhere(0.2, 0.2));
  const TransferFunction open = TransferFunction::emission_extinction(
      curve({{0.0, 1.0}, {0.5, 1.0}, {0.5, 0.0}, {0.7, 0.0}, {0.7, 1.0}}),
      curve({{0.0, 1.0}, {0.5, 1.0}, {0.5, 0.0}, {0.7, 0.0}, {0.7, 1.0}}));
  EXPECT_FALSE(open.transparent_on(0.5, 0.5));
  EXPECT_FALSE(open.transparent_on(0.7, 0.7));
  EXPECT_TRUE(open.transparent_somewhere(0.0, 1.0));  // (0.5, 0.7): only a midpoint shows it
  EXPECT_TRUE(open.transparent_somewhere(0.55, 0.65));
  EXPECT_FALSE(open.transparent_somewhere(0.7, 1.0));
  const TransferFunction oc = TransferFunction::opacity_color(curve({{0.0, 0.0}, {0.4, 0.0}, {1.0, 0.5}}),
                                                              curve({{0.0, 1.0}, {1.0, 1.0}}), 1.0);
  EXPECT_TRUE(oc.transparent_somewhere(0.3, 2.0));
  EXPECT_FALSE(oc.transparent_somewhere(0.41, 2.0));
  const TransferFunction never = TransferFunction::opacity_color(curve({{0.0, 0.1}, {1.0, 0.5}}),
                                                                 curve({{0.0, 0.0}, {1.0, 1.0}}), 1.0);
  EXPECT_FALSE(never.transparent_somewhere(-1e300, 1e300));
  // A zero stretch between two jumps found between ends near the largest double (no overflow).
  const TransferFunction far = TransferFunction::emission_extinction(
      curve({{1e308, 1.0}, {1.5e308, 1.0}, {1.5e308, 0.0}, {1.7e308, 0.0}, {1.7e308, 1.0}}),
      curve({{1e308, 1.0}, {1.5e308, 1.0}, {1.5e308, 0.0}, {1.7e308, 0.0}, {1.7e308, 1.0}}));
  EXPECT_TRUE(far.transparent_somewhere(1.2e308, 1.79e308));
}

// Past 2^53 a value minus 1 is the value itself, as is the midpoint of two neighbouring doubles:
// the branch below a jump at 1.2 x 2^54 was sampled above it, so the jump had size 0 and the
// function looked proportional (g = 8/3 tau everywhere) where it is 0.3 / 0.8 below the jump.
TEST(TransferFunction, BranchesOfAJumpPast2To53AreEachTheirOwn) {
  const double level = 1.2 * 0x1p54, below = level - 0x1p20;
  const TransferFunction tf = TransferFunction::emission_extinction(curve({{level, 0.3}, {level, 4.0}}),
                                                                    curve({{level, 0.8}, {level, 1.5}}));
  EXPECT_FALSE(tf.emission_per_extinction().has_value());
  EXPECT_EQ(tf.signed_jump_at(level).emission, 3.7);
  EXPECT_EQ(tf.signed_jump_at(level).extinction, 0.7);
  EXPECT_EQ(tf.emission(below), 0.3);
  EXPECT_EQ(tf.emission(level), 4.0);
  EXPECT_EQ(tf.max_emission_per_extinction(), 4.0 / 1.5);
  // Two breakpoints one ulp apart: the stretch between them is the lower one alone.
  const double next = std::nextafter(level, 2 * level);
  EXPECT_EQ(value_inside(level, next), level);
  EXPECT_LT(value_inside(-std::numeric_limits<double>::infinity(), level), level);
  EXPECT_LT(value_inside(-std::numeric_limits<double>::infinity(), -1e308), -1e308);
  EXPECT_EQ(value_inside(level, std::numeric_limits<double>::infinity()), level);
  EXPECT_EQ(value_inside(0.25, 0.75), 0.5);
}

// Lines are anchored at their end of smaller |y| (no cancellation), so a line rounds at its other
// end; what finish() derives from the ends (maxima, jumps) comes from the control values: a kink
// has no jump, and the maxima are the largest control values, on awkward random curves.
TEST(TransferFunction, KinksHaveNoJumpAndMaximaAreControlValues) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> y(0.0, 3.0), step(1e-3, 0.7);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<ControlPoint> g, tau;
    double v = -0.3, max_g = 0, max_tau = 0;
    for (int i = 0; i < 12; ++i, v += step(rng)) {
      g.push_back({v, y(rng)}), tau.push_back({v, y(rng)});
      max_g = std::max(max_g, g.back().y), max_tau = std::max(max_tau, tau.back().y);
    }
    const TransferFunction tf = TransferFunction::emission_extinction(curve(g), curve(tau));
    for (const ControlPoint& p : g) {
      EXPECT_EQ(tf.signed_jump_at(p.v).emission, 0.0) << trial << " at " << p.v;
      EXPECT_EQ(tf.signed_jump_at(p.v).extinction, 0.0) << trial << " at " << p.v;
    }
    EXPECT_EQ(tf.max_emission(), max_g) << trial;
    EXPECT_EQ(tf.max_extinction(), max_tau) << trial;
  }
}

// From (-1e6, 1e6) down to (0, 0) at v = -0.1: anchored at the left end it was 1e6 - (1e6 - 0.1),
// off by ulps of 1e6; anchored at (0, 0) it is 0.1 to an ulp.
TEST(TransferFunction, LinesDoNotCancelFarFromTheirAnchor) {
  const PiecewiseLinear down({{-1e6, 1e6}, {0, 0}});
  EXPECT_NEAR(down(-0.1), 0.1, 0x1p-52 * 0.1);
  const PiecewiseLinear up({{0, 0}, {1e6, 1e6}});
  EXPECT_NEAR(up(0.1), 0.1, 0x1p-52 * 0.1);
}

// A span or slope that overflows made a piece's line 0 (slope 1 / inf) or NaN (inf x 0): refused.
TEST(TransferFunction, OverflowingSpansAndSlopesAreRefused) {
  EXPECT_THROW(PiecewiseLinear({{-1e308, 0}, {1e308, 1}}), std::invalid_argument);
  EXPECT_THROW(PiecewiseLinear({{0, 0}, {1e-310, 1e10}}), std::invalid_argument);
  EXPECT_NO_THROW(PiecewiseLinear({{-1e307, 0}, {1e307, 1}}));
  EXPECT_NO_THROW(PiecewiseLinear({{0, 0}, {1e-300, 1e-10}, {1e-300, 1}}));  // a jump has no slope
}

}  // namespace
}  // namespace vrv
