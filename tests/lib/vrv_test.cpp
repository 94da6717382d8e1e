// The library API of lib/vrv.h: projection batches equal the per-ray functions bit for bit,
// whatever the thread count; a bad tolerance or image is refused with the command line's message.
#include "lib/vrv.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "lib/util/parallel.h"

namespace vrv {
namespace {

std::vector<Ray> some_rays() {
  return {make_ray({-3, 0.5, 0}, {1, 0, 0}), make_ray({0, 0, -5}, {0.1, 0.2, 1}), make_ray({-3, 5, 0}, {1, 0, 0})};
}

TEST(LibraryProjections, BatchesAreThePerRayValues) {
  const Scene scene = default_scene();
  const auto rays = some_rays();
  for (ProjectionMode mode : {ProjectionMode::xray, ProjectionMode::mip_classified}) {
    std::vector<ProjectionResult> one, two;
    {
      const ThreadLimit limit(1);
      one = projection_values(scene, rays, mode);
    }
    {
      const ThreadLimit limit(2);
      two = projection_values(scene, rays, mode);
    }
    ASSERT_EQ(one.size(), rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const ProjectionResult r = projection_reference(scene, rays[i], mode);
      EXPECT_EQ(one[i].value, r.value);
      EXPECT_EQ(two[i].value, r.value);
      EXPECT_EQ(one[i].error_estimate, r.error_estimate);
    }
    EXPECT_FALSE(one[2].hit);
  }
  DiscreteProjectionConfig c;
  c.sampling.strategy = Strategy::step;
  c.sampling.step = 0.01;
  const auto d = discrete_projection_values(scene, rays, c);
  for (std::size_t i = 0; i < rays.size(); ++i) EXPECT_EQ(d[i].value, discrete_projection(scene, rays[i], c).value);
}

TEST(LibraryProjections, BadToleranceIsRefused) {
  const auto rays = some_rays();
  try {
    projection_values(default_scene(), rays, ProjectionMode::mip, {-1});
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("--tol:", 0), 0u) << e.what();
  }
}

// RGB scenes: color_reference_values is each channel's grey reference_values bit for bit where
// one channel alone asks for the panels all ask for (three equal channels), and the grey calls
// refuse the scene instead of integrating its red channel.
TEST(LibraryColor, GreyCallsRefuseAnRgbSceneAndColorValuesArePerChannel) {
  const Scene rgb = parse_scene(R"([volume]
min = [-1.0, -1.0, -1.0]
max = [1.0, 1.0, 1.0]
[field]
kind = "marschner_lobb"
[transfer]
emission = [[0.0, 0.1, 0.1, 0.1], [1.0, 0.9, 0.9, 0.9]]
extinction = [[0.0, 0.2], [1.0, 1.2]]
[background]
color = [0.3, 0.3, 0.3]
)", "rgb.toml");
  const Camera camera = scene_camera(rgb, 6, 5);
  const std::vector<Ray> rays = camera_rays(camera);
  EXPECT_THROW(reference_values(rgb, rays), std::invalid_argument);
  EXPECT_THROW(render_reference_image(rgb, camera), std::invalid_argument);
  EXPECT_THROW(discrete_values(rgb, rays, DiscreteConfig{}), std::invalid_argument);
  EXPECT_THROW(color_reference_values(default_scene(), rays), std::invalid_argument);
  const std::vector<ChannelsReferenceResult> three = color_reference_values(rgb, rays, {1e-11});
  const std::vector<ReferenceResult> one = reference_values(channel_scene(rgb, 1), rays, {1e-11});
  ASSERT_EQ(three.size(), one.size());
  for (std::size_t i = 0; i < one.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(three[i].channel[c].value, one[i].value) << i;
      EXPECT_EQ(three[i].channel[c].error_estimate, one[i].error_estimate) << i;
    }
}

// A ValueImage is a grey ImageF64 filled as a plain struct: one of more channels, or whose pixels
// do not fill its size, is refused by verify naming the image, before any reference is computed.
TEST(LibraryVerify, ValueImagesOfTheWrongShapeAreRefused) {
  const Scene scene = default_scene();
  const auto message = [&](const ValueImage& bad) {
    try {
      verify(scene, {ValueImage{4, 4, std::vector<double>(16)}, bad}, {0.1, 0.05});
    } catch (const VerifyInputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  ValueImage rgb{4, 4, std::vector<double>(48)};
  rgb.channels = 3;
  EXPECT_EQ(message(rgb), "image 1 (step 0.05): 3 channels (a ValueImage is grey: give ChannelImages for more)");
  EXPECT_EQ(message(ValueImage{4, 4, std::vector<double>(15)}), "image 1 (step 0.05): 15 values for 4 x 4 pixels");
  EXPECT_EQ(message(ValueImage{4, 4}), "image 1 (step 0.05): 0 values for 4 x 4 pixels");
  // The braces fill the members in order, as when ValueImage was a plain struct.
  const ValueImage grey{4, 4, std::vector<double>(16, 0.5), 7, 1e-9};
  EXPECT_EQ(grey.at(3, 3), 0.5);
  EXPECT_EQ(grey.channels, 1);
  EXPECT_EQ(grey.work, 7);
  EXPECT_EQ(grey.max_error_estimate, 1e-9);
}

}  // namespace
}  // namespace vrv
