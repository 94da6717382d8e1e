// lib/verify on an RGB scene: each image channel judged against its own channel's reference (its
// background, its transfer-function jumps), the diagnosis on the worst channel naming the colour
// table's convention, channels matched by name, swapped channels named, RGBA in both alpha
// conventions, and an image without three colour channels refused.  The images are the toy
// renderer's (tests/lib/toy_renderer_conventions.h, not vrv's raycaster), one channel at a time.
#include <algorithm>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "lib/option_error.h"
#include "lib/scene_file.h"
#include "lib/verify.h"
#include "tests/lib/toy_renderer_conventions.h"
#include "tests/lib/verify/verify_toy.h"

namespace vrv::verify_color_test {

using verify_toy::fault_of;

// Channels that differ (a colour jump at 0.55 in green only), a coloured background.
constexpr const char* kScene = R"(
[volume]
min = [-1.0, -1.0, -1.0]
max = [1.0, 1.0, 1.0]
[field]
kind = "marschner_lobb"
[transfer]
opacity = [[0.0, 0.0], [0.3, 0.05], [1.0, 0.6]]
color = [[0.0, 0.2, 0.9, 0.1], [0.55, 1.0, 0.1, 0.3], [0.55, 1.0, 0.7, 0.3], [1.0, 0.5, 0.4, 1.0]]
unit_length = 0.25
[background]
color = [0.1, 0.3, 0.05]
[camera]
eye = [1.5, 1.0, -4.0]
target = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fov = 40.0
width = 20
height = 20
)";

const Scene& rgb_scene() {
  static const Scene scene = parse_scene(kScene, "rgb.toml");
  return scene;
}

// Channel k of the toy's image at step h (over the channel's background, or over `background`).
std::vector<double> toy_channel(int k, double h, const toy::RendererConvention& c = {},
                                std::optional<double> background = std::nullopt) {
  Scene one = channel_scene(rgb_scene(), k);
  if (background) one.background = *background;
  return toy::render(one, *one.camera, h, c);
}

// The toy's RGB images; plane i holds the scene's channel order[i], named names[i].
std::vector<ImageWithStep> rgb_images(const toy::RendererConvention& c = {}, std::array<int, 3> order = {0, 1, 2},
                                      std::vector<std::string> names = {"R", "G", "B"}) {
  std::vector<ImageWithStep> out;
  for (double h : verify_toy::kThreeSteps) {
    std::vector<std::vector<double>> planes;
    for (int k : order) planes.push_back(toy_channel(k, h, c));
    ChannelImage im = verify_toy::planar_image(20, 20, planes, names);
    im.pixel_type = "double";
    out.push_back({fmt::format("toy_{}", h), h, std::move(im)});
  }
  return out;
}

// A straight-colour renderer: every channel its own model to rounding, nothing swapped.
TEST(VerifyColor, EachChannelAgainstItsOwnReference) {
  const VerifyReport r = verify_images(rgb_scene(), rgb_images(), {});
  EXPECT_TRUE(r.pass) << fmt::format("{}", fmt::join(r.failures, "; "));
  EXPECT_EQ(r.reference_channels, 3);
  ASSERT_EQ(r.reference_image.size(), 3u * 20 * 20);
  ASSERT_EQ(r.channels.size(), 9u);
  EXPECT_EQ(r.channels[0].channel, "R");
  EXPECT_EQ(r.channels[2].channel, "B");
  ASSERT_TRUE(r.diagnosis_channel.has_value());
  ASSERT_FALSE(r.diagnosis.empty());
  EXPECT_EQ(r.diagnosis.front().color, "straight") << r.diagnosis.front().name;
  EXPECT_LT(r.diagnosis.front().rms, 1e-13) << r.diagnosis.front().name;
  EXPECT_EQ(fault_of(r, FaultKind::swapped_channels), nullptr);
  // Green's jump is green's alone: its tf_jump region holds pixels, red's and blue's none.
  EXPECT_GT(r.reference.jump_pixels, 0);
  EXPECT_NE(r.channels[1].region(Region::tf_jump), nullptr);
  EXPECT_EQ(r.channels[0].region(Region::tf_jump), nullptr);
  // The channels differ, so judging one against another's reference would show: every channel's
  // finest error is far below the channels' differences.
  for (int c = 0; c < 3; ++c) EXPECT_LT(r.channels[6 + c].all().rms, 0.05) << c;
}

// A renderer reading its colour table premultiplied: the diagnosis names the convention.
TEST(VerifyColor, PremultipliedColourTableIsNamed) {
  const VerifyReport r = verify_images(rgb_scene(), rgb_images({.premultiplied = true}), {});
  ASSERT_FALSE(r.diagnosis.empty());
  EXPECT_EQ(r.diagnosis.front().color, "premultiplied") << r.diagnosis.front().name;
  EXPECT_LT(r.diagnosis.front().rms, 1e-13) << r.diagnosis.front().name;
}

// Planes in another order under their own names: matched by name, nothing wrong.
TEST(VerifyColor, ChannelsAreMatchedByName) {
  const VerifyReport r = verify_images(rgb_scene(), rgb_images({}, {2, 0, 1}, {"B", "R", "G"}), {});
  EXPECT_TRUE(r.pass) << fmt::format("{}", fmt::join(r.failures, "; "));
  EXPECT_EQ(fault_of(r, FaultKind::swapped_channels), nullptr);
  EXPECT_LT(r.diagnosis.front().rms, 1e-13);
}

// Blue written where red belongs (a BGR framebuffer read as RGB): named, with the order it
// matches, and the verification fails.
TEST(VerifyColor, SwappedChannelsAreNamed) {
  const VerifyReport r = verify_images(rgb_scene(), rgb_images({}, {2, 1, 0}), {});
  const Fault* swap = fault_of(r, FaultKind::swapped_channels);
  ASSERT_NE(swap, nullptr);
  EXPECT_NE(swap->evidence.find("match the reference's (B, G, R)"), std::string::npos) << swap->evidence;
  EXPECT_FALSE(r.pass);
  EXPECT_TRUE(std::any_of(r.failures.begin(), r.failures.end(),
                          [](const std::string& f) { return f.rfind("swapped channels: ", 0) == 0; }));
}

// A fault in green alone (its emission 5 % high): the diagnosis reads green.
TEST(VerifyColor, DiagnosisReadsTheWorstChannel) {
  std::vector<ImageWithStep> images = rgb_images();
  for (ImageWithStep& im : images)
    for (std::size_t i = 0; i < im.image.pixel_count(); ++i) im.image.value(i, 1) *= 1.05;
  const VerifyReport r = verify_images(rgb_scene(), images, {});
  EXPECT_EQ(r.diagnosis_channel.value_or(""), "G");
  EXPECT_EQ(fault_of(r, FaultKind::swapped_channels), nullptr);
}

// RGBA rendered over nothing: colour C = I(background 0), alpha = 1 - (I(1) - I(0)); straight
// colour is C / alpha.  Composited over each channel's own background (they differ), both
// conventions give the RGB images' errors to rounding, in every channel and image.
TEST(VerifyColor, RgbaInBothConventions) {
  const VerifyReport rgb = verify_images(rgb_scene(), rgb_images(), {});
  for (AlphaMode mode : {AlphaMode::premultiplied, AlphaMode::straight}) {
    std::vector<ImageWithStep> images;
    for (double h : verify_toy::kThreeSteps) {
      std::vector<std::vector<double>> planes;
      std::vector<double> alpha;
      for (int k = 0; k < 3; ++k) {
        std::vector<double> c = toy_channel(k, h, {}, 0.0), one = toy_channel(k, h, {}, 1.0);
        if (k == 0)
          for (std::size_t i = 0; i < c.size(); ++i) alpha.push_back(1 - (one[i] - c[i]));
        if (mode == AlphaMode::straight)
          for (std::size_t i = 0; i < c.size(); ++i) c[i] = alpha[i] > 0 ? c[i] / alpha[i] : 0;
        planes.push_back(std::move(c));
      }
      planes.push_back(alpha);
      ChannelImage im = verify_toy::planar_image(20, 20, planes, {"R", "G", "B", "A"});
      ASSERT_EQ(im.alpha, 3);
      images.push_back({fmt::format("rgba_{}", h), h, std::move(im)});
    }
    VerifyOptions opt;
    opt.alpha = mode;
    const VerifyReport r = verify_images(rgb_scene(), images, opt);
    EXPECT_TRUE(r.pass) << fmt::format("{}", fmt::join(r.failures, "; "));
    ASSERT_FALSE(r.diagnosis.empty());
    EXPECT_LT(r.diagnosis.front().rms, 1e-12) << r.diagnosis.front().name;
    ASSERT_EQ(r.channels.size(), 12u);
    EXPECT_TRUE(r.channels[3].alpha);
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(r.channels[4 * k + c].all().rms, rgb.channels[3 * k + c].all().rms, 1e-12) << k << c;
  }
}

// --alpha says how colour relates to alpha: on images without alpha it would be ignored.
TEST(VerifyColor, AlphaConventionWithoutAlphaIsRefused) {
  for (AlphaMode mode : {AlphaMode::premultiplied, AlphaMode::straight}) {
    VerifyOptions opt;
    opt.alpha = mode;
    try {
      verify_images(rgb_scene(), rgb_images(), opt);
      FAIL() << alpha_mode_name(mode) << " was accepted on RGB images";
    } catch (const OptionError& e) {
      EXPECT_EQ(e.option(), Option::alpha);
      EXPECT_NE(std::string(e.what()).find("the images have no alpha channel"), std::string::npos) << e.what();
    }
  }
}

TEST(VerifyColor, ImageWithoutThreeColourChannelsIsRefused) {
  std::vector<ImageWithStep> images = rgb_images();
  for (ImageWithStep& im : images) {
    std::vector<double> red(im.image.pixel_count());
    for (std::size_t i = 0; i < red.size(); ++i) red[i] = im.image.value(i, 0);
    ChannelImage grey(ImageF64(im.image.width, im.image.height, red));
    grey.pixel_type = im.image.pixel_type;
    im.image = std::move(grey);
  }
  try {
    verify_images(rgb_scene(), images, {});
    FAIL() << "a grey image of an RGB scene was verified";
  } catch (const VerifyInputError& e) {
    EXPECT_NE(std::string(e.what()).find("1 colour channel(s) (Y), but the scene is RGB"), std::string::npos)
        << e.what();
  }
}

// A grey scene's three-channel image is judged as before: every channel against the one reference.
TEST(VerifyColor, GreySceneStillTakesAnyChannels) {
  const Scene grey = channel_scene(rgb_scene(), 0);
  std::vector<ImageWithStep> images;
  for (double h : verify_toy::kThreeSteps) {
    const std::vector<double> v = toy::render(grey, *grey.camera, h, {});
    ChannelImage im = verify_toy::planar_image(20, 20, {v, v, v}, {"R", "G", "B"});
    images.push_back({fmt::format("grey_{}", h), h, std::move(im)});
  }
  const VerifyReport r = verify_images(grey, images, {});
  EXPECT_TRUE(r.pass);
  EXPECT_EQ(r.reference_channels, 1);
  EXPECT_FALSE(r.diagnosis_channel.has_value());
  EXPECT_EQ(r.channels[6].all().rms, r.channels[8].all().rms);
}

}  // namespace vrv::verify_color_test
