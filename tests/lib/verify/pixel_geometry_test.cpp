// lib/verify/pixel_geometry: the regions split the pixels.
#include <filesystem>
#include <gtest/gtest.h>

#include "tests/lib/verify/verify_toy.h"

namespace vrv::verify_toy {
namespace {

namespace fs = std::filesystem;

TEST_F(VerifyToy, RegionsSplitThePixels) {
  VerifyOptions o = options();
  o.diagnose = false;
  const VerifyReport r = verify_images(scene, toy_images(scene, toy::Fault::none, "regions"), o);
  long sum = 0;
  for (const RegionStats& s : r.channels[0].regions)
    if (s.region != Region::all) sum += s.pixels;
  EXPECT_EQ(sum, r.channels[0].regions[0].pixels);
  EXPECT_GT(r.reference.silhouette_pixels, 0);
  EXPECT_GT(r.reference.hit_pixels, r.reference.silhouette_pixels);
}

}  // namespace
}  // namespace vrv::verify_toy
