// The transfer-function classes as the exact integral sees them: (a) proportional, (b) general,
// (c) steps, (d) a narrow peak, (e) the opacity / colour convention -- their breakpoints, jumps and
// peak crossings -- on Marschner-Lobb, ray by ray against the independent long-double integral
// (reference_check.h).
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

}  // namespace
}  // namespace vrv
