// studies/engine/study_outputs: the quantile that scales the studies' error maps.
#include "studies/engine/study_outputs.h"

#include <gtest/gtest.h>

namespace vrv {
namespace {

TEST(StudyOutputs, AbsPixelQuantileIsTheNearestRank) {
  Image im(10, 1);
  for (int i = 0; i < 10; ++i) im.pixels[static_cast<std::size_t>(i)] = static_cast<float>(i % 2 ? -(i + 1) : i + 1);
  EXPECT_EQ(abs_pixel_quantile(im, 1.0), 10.0);
  EXPECT_EQ(abs_pixel_quantile(im, 0.9), 9.0);  // rank ceil(9) = 9 of 1..10
  EXPECT_EQ(abs_pixel_quantile(im, 0.0), 1.0);
  EXPECT_EQ(max_abs_pixel(im), 10.0);
  EXPECT_EQ(abs_pixel_quantile(Image(), 0.99), 0.0);
}

}  // namespace
}  // namespace vrv
