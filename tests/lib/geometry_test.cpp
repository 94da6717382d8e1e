#include "lib/geometry.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace vrv {
namespace {

const Box unit_box{Vec3(-1, -1, -1), Vec3(1, 1, 1)};

TEST(Geometry, ClipThroughTheMiddle) {
  const auto iv = clip(make_ray(Vec3(-3, 0, 0), Vec3(2, 0, 0)), unit_box);
  ASSERT_TRUE(iv);
  EXPECT_DOUBLE_EQ(iv->t0, 2);
  EXPECT_DOUBLE_EQ(iv->t1, 4);
}

TEST(Geometry, RayStartingInsideBeginsAtZero) {
  const auto iv = clip(make_ray(Vec3(0.5, 0, 0), Vec3(1, 0, 0)), unit_box);
  ASSERT_TRUE(iv);
  EXPECT_EQ(iv->t0, 0);
  EXPECT_DOUBLE_EQ(iv->t1, 0.5);
}

TEST(Geometry, BoxIsClosedSoEdgesAndFacesCount) {
  const auto edge = clip(make_ray(Vec3(-2, 1, 1), Vec3(1, 0, 0)), unit_box);
  ASSERT_TRUE(edge);
  EXPECT_DOUBLE_EQ(edge->length(), 2);
  const auto face = clip(make_ray(Vec3(-2, 0.3, -1), Vec3(1, 0, 0)), unit_box);
  ASSERT_TRUE(face);
  EXPECT_DOUBLE_EQ(face->length(), 2);
  EXPECT_FALSE(clip(make_ray(Vec3(-2, 1 + 1e-15, 0), Vec3(1, 0, 0)), unit_box));
}

TEST(Geometry, MissesBehindAndBeside) {
  EXPECT_FALSE(clip(make_ray(Vec3(3, 0, 0), Vec3(1, 0, 0)), unit_box));
  EXPECT_FALSE(clip(make_ray(Vec3(-3, 2, 0), Vec3(1, 0, 0)), unit_box));
}

TEST(Geometry, CornerClipIsShortButFinite) {
  // Through the corner region (1, 1, z): a chord of length ~1e-9.
  const Vec3 dir = Vec3(1, -1, 0).normalized();
  const auto iv = clip(make_ray(Vec3(1 - 1e-9, 1 + 1e-15, 0) - 2 * dir, dir), unit_box);
  ASSERT_TRUE(iv);
  EXPECT_GT(iv->length(), 0);
  EXPECT_LT(iv->length(), 2e-9);
}

TEST(Geometry, DirectionIsNormalisedWithoutOverflow) {
  for (double s : {1e-300, 1.0, 1e300}) {
    const Ray r = make_ray(Vec3(0, 0, 0), Vec3(s, 2 * s, -2 * s));
    EXPECT_NEAR(r.direction.norm(), 1, 1e-15);
    EXPECT_NEAR(r.direction.x(), 1.0 / 3, 1e-15);
  }
}

TEST(Geometry, ZeroOrNonFiniteDirectionIsRejected) {
  EXPECT_THROW(make_ray(Vec3(0, 0, 0), Vec3(0, 0, 0)), std::invalid_argument);
  EXPECT_THROW(make_ray(Vec3(0, 0, 0), Vec3(std::nan(""), 0, 0)), std::invalid_argument);
  EXPECT_THROW(make_ray(Vec3(std::numeric_limits<double>::infinity(), 0, 0), Vec3(1, 0, 0)),
               std::invalid_argument);
}

}  // namespace
}  // namespace vrv
