#include "lib/reference_pixels.h"

#include <array>
#include <functional>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include <gtest/gtest.h>

#include "lib/scene_file.h"
#include "lib/vrv.h"

namespace vrv {
namespace {

// Each position gets its own pixel's integral, for the whole image and for a subset.
TEST(ReferencePixels, EveryPositionIsItsPixelsIntegral) {
  const Scene scene = default_scene();
  Camera camera = default_camera(scene.box);
  camera.width = 9;
  camera.height = 7;
  const ReferenceOptions options{1e-8};
  std::vector<ReferenceResult> all(static_cast<std::size_t>(pixel_count(camera)));
  reference_pixels(scene, camera, options, [&](long i, const ReferenceResult& r) { all[i] = r; });
  const std::vector<long> subset{62, 0, 31};
  std::vector<ReferenceResult> some(subset.size());
  reference_pixels(scene, camera, options, [&](long k, const ReferenceResult& r) { some[k] = r; }, {}, subset);
  visit_field(scene, [&](const auto& field) {
    for (long i = 0; i < pixel_count(camera); ++i) {
      const ReferenceResult r =
          integrate_reference(field, scene.box, scene.transfer, scene.background, pixel_ray(camera, i), options);
      EXPECT_EQ(all[i].value, r.value) << i;
      EXPECT_EQ(all[i].error_estimate, r.error_estimate) << i;
      EXPECT_EQ(all[i].evaluations, r.evaluations) << i;
    }
  });
  for (std::size_t k = 0; k < subset.size(); ++k) EXPECT_EQ(some[k].value, all[subset[k]].value) << k;
}

// A pixel of channels is a fixed-width record (what MPI ranks exchange as bytes).
static_assert(std::is_trivially_copyable_v<ChannelsReferenceResult>);

// The image's channels (here grey and alpha) per pixel are the one-ray integral's, kept whole or
// reduced by `keep` before they are put.
TEST(ReferencePixels, ChannelPixelsAreEachRaysChannels) {
  const Scene scene = default_scene();
  const Camera camera = scene_camera(scene, 6, 5);
  const ReferenceOptions options{1e-8};
  const ImageChannels channels(scene, true);
  std::vector<ChannelsReferenceResult> all(static_cast<std::size_t>(pixel_count(camera)));
  image_channel_pixels(scene, camera, channels, options, std::identity(),
                       [&](long i, const ChannelsReferenceResult& r) { all[i] = r; });
  std::vector<double> alpha(all.size());
  image_channel_pixels(scene, camera, channels, options,
                       [](const ChannelsReferenceResult& r) { return r.channel[1].value; },
                       [&](long i, double a) { alpha[i] = a; });
  int opaque = 0;
  visit_field(scene, [&](const auto& field) {
    for (long i = 0; i < pixel_count(camera); ++i) {
      const ChannelsReferenceResult r = integrate_image_channels(field, scene.box, channels, pixel_ray(camera, i), options);
      ASSERT_EQ(all[i].count, 2);
      for (int c = 0; c < 2; ++c) {
        EXPECT_EQ(all[i].channel[c].value, r.channel[c].value) << i << ' ' << c;
        EXPECT_EQ(all[i].channel[c].error_estimate, r.channel[c].error_estimate) << i << ' ' << c;
      }
      EXPECT_EQ(alpha[i], r.channel[1].value) << i;
      opaque += alpha[i] > 0.1;
    }
  });
  EXPECT_GT(opaque, 0) << "some pixels should absorb";
}

TEST(ReferencePixels, MoreChannelsThanAPixelHoldsAreRefused) {
  const Scene scene = default_scene();
  const std::array<ReferenceChannel, kMaxChannels + 1> five{
      {{&scene.transfer, 0}, {&scene.transfer, 0}, {&scene.transfer, 0}, {&scene.transfer, 0}, {&scene.transfer, 0}}};
  visit_field(scene, [&](const auto& field) {
    EXPECT_THROW(integrate_channels_reference(field, scene.box, five, pixel_ray(default_camera(scene.box), 0)),
                 std::invalid_argument);
  });
}

}  // namespace
}  // namespace vrv
