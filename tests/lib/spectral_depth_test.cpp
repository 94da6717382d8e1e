// The depth halves the channels of a walk share (lib/spectral_depth.h): found only under the same
// key, Phi only where it was made, e^-Phi forgotten when a slot is reused, nothing after clear().
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
  SpectralDepth& made = share.slot(key(0.1, 0.2, 9));
  made.has_phi = true;
  made.dphi = 0.5;
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
  SpectralDepth& depth_only = share.slot(key(0.0, 1.0, 9));
  depth_only.has_phi = false;
  EXPECT_NE(share.find(key(0.0, 1.0, 9), false), nullptr);
  EXPECT_EQ(share.find(key(0.0, 1.0, 9), true), nullptr) << "a depth-only half has no Phi at the nodes";
  share.clear();
  EXPECT_EQ(share.find(key(0.0, 1.0, 9), false), nullptr);
}

TEST(SpectralDepthShare, AReusedSlotForgetsItsAttenuation) {
  SpectralDepthShare share;
  SpectralDepth& first = share.slot(key(0.0, 1.0, 9));
  first.has_attenuation = true;
  first.at_depth = 0.25;
  share.clear();
  EXPECT_FALSE(share.slot(key(2.0, 3.0, 9)).has_attenuation);
}

}  // namespace
}  // namespace vrv::detail::spectral_depth_test
