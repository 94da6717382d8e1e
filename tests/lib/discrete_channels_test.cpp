// The one discrete cast of a scene's channels (lib/discrete_channels.h): an RGB scene's channel c is
// the grey cast of channel_scene(scene, c) bit for bit, the samples are summed over the channels, a
// grey scene is its one grey cast, and the image form is the per-ray form through the camera.
#include <functional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "lib/discrete_channels.h"
#include "lib/vrv.h"
#include "tests/lib/scene_text.h"

namespace vrv::discrete_channels_test {

// Three different channels (each its own emission and background) over one extinction.
const std::string kRgb = test::unit_box_scene("kind = \"marschner_lobb\"", R"([transfer]
emission = [[0.0, 0.1, 0.8, 0.3], [0.5, 0.9, 0.2, 0.3], [1.0, 0.4, 0.6, 0.0]]
extinction = [[0.0, 0.2], [1.0, 3.0]]
[background]
color = [0.3, 0.05, 0.6]
)");

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
  const ImageF64 image = discrete_channel_image(rgb, camera, config);
  const auto values = discrete_channel_values(rgb, camera_rays(camera), config);
  ASSERT_EQ(image.channels, 3);
  ASSERT_EQ(image.pixel_count(), values.size());
  for (int c = 0; c < 3; ++c)
    for (std::size_t i = 0; i < values.size(); ++i) EXPECT_EQ(image.value(i, c), values[i].value[c]) << c << ' ' << i;
  EXPECT_EQ(discrete_channel_image(default_scene(), camera, config).channels, 1);
}

TEST(DiscreteChannels, BadConfigurationAndCameraAreRefused) {
  const Scene rgb = parse_scene(kRgb, "rgb.toml");
  Camera camera = scene_camera(rgb, 4, 4);
  const std::vector<Ray> rays = camera_rays(camera);
  DiscreteConfig bad = trapezoid(0.05);
  bad.oversample = 0;
  EXPECT_THROW(discrete_channel_values(rgb, rays, bad), std::invalid_argument);
  EXPECT_THROW(discrete_channel_image(rgb, camera, bad), std::invalid_argument);
  camera.width = 0;
  EXPECT_THROW(discrete_channel_image(rgb, camera, trapezoid(0.05)), std::invalid_argument);
}

// A shaded RGB grid whose colour reaches past its opacity's breakpoints (tables span the colour's).
const std::string kShadedGridRgb = test::unit_box_scene(
    "kind = \"grid\"\nresolution = [9, 9, 9]\n[field.source]\nkind = \"marschner_lobb\"",
    std::string(R"([transfer]
opacity = [[0.0, 0.0], [0.5, 0.3], [0.5, 0.7], [1.0, 0.2]]
color = [[-0.2, 1.0, 0.0, 0.2], [0.5, 0.1, 1.0, 0.3], [1.2, 0.8, 0.2, 0.9]]
unit_length = 0.1
[background]
color = [0.3, 0.05, 0.6]
)") + std::string(test::kPhong));

// The discrete A is 1 - the colour casts' transmittance; it must equal, bit for bit, 1 - a cast of
// the same extinction with no emission over a background of 1, under every option that changes
// which samples composite or how (the reference integrator's alpha channel is that cast).
TEST(DiscreteChannels, AlphaIsTheZeroEmissionCastBitwise) {
  const Scene scene = parse_scene(kShadedGridRgb, "shaded.toml");
  const std::vector<Ray> rays = camera_rays(scene_camera(scene, 6, 5));
  const std::vector<std::pair<std::string, std::function<void(DiscreteConfig&)>>> variants = {
      {"riemann", [](DiscreteConfig& c) { c.rule = SegmentRule::riemann; }},
      {"alpha distance", [](DiscreteConfig& c) { c.rule = SegmentRule::alpha, c.opacity_unit = OpacityUnit::per_unit_distance; }},
      {"alpha premultiplied, lee-newman 4 centred", [](DiscreteConfig& c) {
         c.rule = SegmentRule::alpha, c.color = ColorConvention::premultiplied, c.oversample = 4;
         c.correction = Correction::lee_newman, c.centred_oversamples = true;
         c.sampling.strategy = Strategy::step;
       }},
      {"exact_linear", [](DiscreteConfig& c) { c.rule = SegmentRule::exact_linear; }},
      {"moreland", [](DiscreteConfig& c) { c.rule = SegmentRule::moreland; }},
      {"back to front", [](DiscreteConfig& c) { c.compositing = Compositing::back_to_front; }},
      {"termination and skip", [](DiscreteConfig& c) { c.termination = 0.6, c.skip_below = 0.02; }},
      {"tables 64", [](DiscreteConfig& c) { c.table_size = 64; }},
      {"tables 1024, alpha", [](DiscreteConfig& c) { c.table_size = 1024, c.rule = SegmentRule::alpha; }},
      {"pre-classified", [](DiscreteConfig& c) { c.classification = Classification::pre; }},
      {"float", [](DiscreteConfig& c) { c.precision = Precision::single_precision; }},
      {"shaded at nodes", [](DiscreteConfig& c) {
         c.classification = Classification::pre, c.gradient = GradientScheme::nodes, c.shade_at = ShadeAt::nodes;
       }},
  };
  const TransferFunction no_emission = scene.color->transfer[0].without_emission();
  for (const auto& variant : variants) {
    const std::string& name = variant.first;  // a lambda cannot capture a structured binding in clang 14
    DiscreteConfig config = trapezoid(0.07);
    variant.second(config);
    validate(config, true);
    visit_field(scene, [&](const auto& field) {
      const DiscreteChannelCaster with_alpha(field, scene, config, true);
      const DiscreteRaycaster transmittance(field, scene.box, no_emission, 1.0, config, scene.shading_or_null(),
                                            scene.dims);
      int opaque = 0;
      for (std::size_t i = 0; i < rays.size(); ++i) {
        const double t = transmittance.cast(rays[i]).value;
        EXPECT_EQ(with_alpha.cast(rays[i]).value[3], 1 - t) << name << ", ray " << i;
        opaque += t < 0.5;
      }
      EXPECT_GT(opaque, 0) << name << ": no ray accumulates much opacity, so the check is weak";
    });
  }
}

}  // namespace vrv::discrete_channels_test
