// The one discrete cast of a scene's channels (lib/discrete_channels.h): an RGB scene's channel c is
// the grey cast of channel_scene(scene, c) bit for bit, the samples are summed over the channels, a
// grey scene is its one grey cast, and the image form is the per-ray form through the camera.
#include <span>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "lib/discrete_channels.h"
#include "lib/vrv.h"

namespace vrv::discrete_channels_test {

// Three different channels (each its own emission and background) over one extinction.
constexpr const char* kRgb = R"([volume]
min = [-1.0, -1.0, -1.0]
max = [1.0, 1.0, 1.0]
[field]
kind = "marschner_lobb"
[transfer]
emission = [[0.0, 0.1, 0.8, 0.3], [0.5, 0.9, 0.2, 0.3], [1.0, 0.4, 0.6, 0.0]]
extinction = [[0.0, 0.2], [1.0, 3.0]]
[background]
color = [0.3, 0.05, 0.6]
)";

DiscreteConfig trapezoid(double step) {
  DiscreteConfig config;
  config.rule = SegmentRule::trapezoid;
  config.sampling.step = step;
  return config;
}

TEST(DiscreteChannels, EachRgbChannelIsItsGreySceneCastBitwise) {
  const Scene rgb = parse_scene(kRgb, "rgb.toml");
  const std::vector<Ray> rays = camera_rays(scene_camera(rgb, 7, 5));
  const DiscreteConfig config = trapezoid(0.05);
  const std::vector<ChannelsDiscreteResult> all = discrete_channel_values(rgb, rays, config);
  ASSERT_EQ(all.size(), rays.size());
  std::vector<long> samples(rays.size(), 0);
  for (int c = 0; c < 3; ++c) {
    const std::vector<DiscreteResult> grey = discrete_values(channel_scene(rgb, c), rays, config);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      EXPECT_EQ(all[i].value[c], grey[i].value) << "channel " << c << " ray " << i;
      samples[i] += grey[i].samples;
    }
  }
  for (std::size_t i = 0; i < rays.size(); ++i) EXPECT_EQ(all[i].samples, samples[i]) << i;
  // The channels differ (a mix-up of transfer functions or backgrounds would show).
  EXPECT_NE(all[0].value[0], all[0].value[1]);
  EXPECT_NE(all[0].value[1], all[0].value[2]);
}

TEST(DiscreteChannels, GreySceneIsItsOneCast) {
  const Scene grey = default_scene();
  const std::vector<Ray> rays = camera_rays(scene_camera(grey, 6, 4));
  const DiscreteConfig config = trapezoid(0.02);
  const auto all = discrete_channel_values(grey, rays, config);
  const auto one = discrete_values(grey, rays, config);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    EXPECT_EQ(all[i].value[0], one[i].value) << i;
    EXPECT_EQ(all[i].samples, one[i].samples) << i;
    EXPECT_EQ(all[i].value[1], 0.0);
  }
}

TEST(DiscreteChannels, PlanesAreTheCameraRaysValuesPerChannel) {
  const Scene rgb = parse_scene(kRgb, "rgb.toml");
  const Camera camera = scene_camera(rgb, 9, 4);
  const DiscreteConfig config = trapezoid(0.05);
  const auto planes = discrete_channel_planes(rgb, camera, config);
  const auto values = discrete_channel_values(rgb, camera_rays(camera), config);
  ASSERT_EQ(planes.size(), 3u);
  for (int c = 0; c < 3; ++c) {
    ASSERT_EQ(planes[c].size(), values.size());
    for (std::size_t i = 0; i < values.size(); ++i) EXPECT_EQ(planes[c][i], values[i].value[c]) << c << ' ' << i;
  }
  EXPECT_EQ(discrete_channel_planes(default_scene(), camera, config).size(), 1u);
}

TEST(DiscreteChannels, BadConfigurationAndCameraAreRefused) {
  const Scene rgb = parse_scene(kRgb, "rgb.toml");
  Camera camera = scene_camera(rgb, 4, 4);
  const std::vector<Ray> rays = camera_rays(camera);
  DiscreteConfig bad = trapezoid(0.05);
  bad.oversample = 0;
  EXPECT_THROW(discrete_channel_values(rgb, rays, bad), std::invalid_argument);
  EXPECT_THROW(discrete_channel_planes(rgb, camera, bad), std::invalid_argument);
  camera.width = 0;
  EXPECT_THROW(discrete_channel_planes(rgb, camera, trapezoid(0.05)), std::invalid_argument);
}

}  // namespace vrv::discrete_channels_test
