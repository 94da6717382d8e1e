#include "lib/projection/projection_mode.h"

#include <gtest/gtest.h>

namespace vrv {
namespace {

TEST(ProjectionMode, NamesRoundTrip) {
  for (auto m : {ProjectionMode::xray, ProjectionMode::xray_classified, ProjectionMode::mip, ProjectionMode::mip_classified})
    EXPECT_EQ(parse_projection_mode(projection_mode_name(m)), m);
  EXPECT_FALSE(parse_projection_mode("MIP"));
  EXPECT_FALSE(parse_projection_mode(""));
  EXPECT_EQ(projection_mode_list(), "xray, xray_classified, mip, mip_classified");
}

TEST(ProjectionMode, Kinds) {
  EXPECT_TRUE(is_mip(ProjectionMode::mip_classified));
  EXPECT_FALSE(is_mip(ProjectionMode::xray));
  EXPECT_TRUE(is_classified(ProjectionMode::xray_classified));
  EXPECT_FALSE(is_classified(ProjectionMode::mip));
}

}  // namespace
}  // namespace vrv
