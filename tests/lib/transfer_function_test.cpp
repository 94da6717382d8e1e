// The transfer-function classes as the exact integral sees them: (a) proportional, (b) general,
// (c) steps, (d) a narrow peak, (e) the opacity / colour convention -- their breakpoints, jumps and
// peak crossings -- on Marschner-Lobb, ray by ray against the independent long-double integral
// (reference_check.h); and where a transfer function is transparent (the empty-space search).
#include "lib/transfer_function.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace vrv
