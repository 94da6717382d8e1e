// The depth halves the channels of a walk share (lib/spectral_depth.h): found only under the same
// key, Phi only where it was made, nothing after clear(), at most kMaxPieces kept.
#include "lib/spectral_depth.h"

#include <gtest/gtest.h>

namespace vrv::detail::spectral_depth_test {
namespace {

SpectralDepthKey key(double c, double d, int n) {
  SpectralDepthKey k;
  k.c = c, k.d = d, k.n = n;
  k.extinction = Line{0.0, 0.2, 2.0};
  k.extinction_slope = 2.0;
  return k;
}

TEST(SpectralDepthShare, FindsOnlyTheSamePieceRuleAndExtinction) {
  SpectralDepthShare share;
  SpectralDepth* made = share.slot(key(0.1, 0.2, 9));
  ASSERT_NE(made, nullptr);
  made->has_phi = true;
  made->dphi = 0.5;
  ASSERT_NE(share.find(key(0.1, 0.2, 9), true), nullptr);
  EXPECT_EQ(share.find(key(0.1, 0.2, 9), true)->dphi, 0.5);
  EXPECT_EQ(share.find(key(0.1, 0.2, 17), true), nullptr);
  EXPECT_EQ(share.find(key(0.1, 0.25, 9), true), nullptr);
  SpectralDepthKey other = key(0.1, 0.2, 9);
  other.extinction.slope = 3.0;
  EXPECT_EQ(share.find(other, true), nullptr);
  other = key(0.1, 0.2, 9);
  other.convention = Convention::opacity_color;
  EXPECT_EQ(share.find(other, true), nullptr);
  other = key(0.1, 0.2, 9);
  other.extinction_slope = 2.5;
  EXPECT_EQ(share.find(other, true), nullptr);
}

TEST(SpectralDepthShare, PhiOnlyWhereMadeAndNothingAfterClear) {
  SpectralDepthShare share;
  share.slot(key(0.0, 1.0, 9))->has_phi = false;
  EXPECT_NE(share.find(key(0.0, 1.0, 9), false), nullptr);
  EXPECT_EQ(share.find(key(0.0, 1.0, 9), true), nullptr) << "a depth-only half has no Phi at the nodes";
  share.clear();
  EXPECT_EQ(share.find(key(0.0, 1.0, 9), false), nullptr);
}

// Past kMaxPieces nothing more is kept (a panel split to the work cap), and every kept piece is
// found in any order of asking.
TEST(SpectralDepthShare, KeepsAtMostItsCapAndFindsInAnyOrder) {
  SpectralDepthShare share;
  const int cap = static_cast<int>(SpectralDepthShare::kMaxPieces);
  for (int i = 0; i < cap; ++i) {
    SpectralDepth* slot = share.slot(key(i, i + 1, 9));
    ASSERT_NE(slot, nullptr) << i;
    slot->has_phi = true, slot->dphi = i;
  }
  EXPECT_EQ(share.slot(key(cap, cap + 1, 9)), nullptr);
  for (int i : {5, 6, 0, cap - 1, 3, 3}) {
    const SpectralDepth* found = share.find(key(i, i + 1, 9), true);
    ASSERT_NE(found, nullptr) << i;
    EXPECT_EQ(found->dphi, i);
  }
  share.clear();
  EXPECT_NE(share.slot(key(0, 1, 9)), nullptr);
}

}  // namespace
}  // namespace vrv::detail::spectral_depth_test
