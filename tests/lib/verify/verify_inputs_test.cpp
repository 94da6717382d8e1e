// lib/verify/verify_inputs and verify_options: bad images and bad options are refused in one line
// naming the image or the option.
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/lib/verify/verify_toy.h"

namespace vrv::verify_toy {
namespace {

namespace fs = std::filesystem;

TEST_F(VerifyToy, BadInputIsOneLineNamingTheImage) {
  std::vector<ImageWithStep> images = toy_images(scene, toy::Fault::none, "bad");
  VerifyOptions o = options();
  o.diagnose = false;
  auto message = [&](const std::vector<ImageWithStep>& ims) {
    try {
      verify_images(scene, ims, o);
    } catch (const VerifyInputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  auto nan = images;
  nan[1].image.pixels[5] = NAN;
  EXPECT_NE(message(nan).find(images[1].name + ": pixel (5, 0) channel Y is nan"), std::string::npos) << message(nan);
  auto small = images;
  small[2].image.width = 20;
  EXPECT_NE(message(small).find("size 20 x 32 differs"), std::string::npos) << message(small);
  auto repeated = images;
  repeated[3].step = repeated[0].step;
  EXPECT_NE(message(repeated).find("repeats"), std::string::npos);
  o.allow_nan = true;
  const VerifyReport counted = verify_images(scene, nan, o);
  long total = 0;
  for (const ChannelReport& c : counted.channels) total += c.nan_count;
  EXPECT_EQ(total, 1);
}

// vrv verify's options and vrv.verify's keywords go through one check: each bad value is one
// line naming the command-line option, the first bad one in the documented order.
TEST(VerifySettings, EachBadValueIsRefusedNamingItsOption) {
  const auto message = [](VerifySettings s) {
    VerifyOptions o;
    try {
      apply(s, o);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(message({0, 0.25, "rms", 0}), "--tol: must be a positive finite number, got 0");
  EXPECT_EQ(message({1e-10, 0, "rms", 0}), "--order-tolerance: must be positive");
  EXPECT_EQ(message({1e-10, 0.25, "fraction_over", 0}), "--order-metric: 'fraction_over' is not one of max, mean, rms, p99");
  EXPECT_EQ(message({1e-10, 0.25, "median", 0}), "--order-metric: 'median' is not one of max, mean, rms, p99");
  EXPECT_EQ(message({1e-10, 0.25, "rms", -1}), "--unit-distance: must be positive and finite (0, the default: the largest step)");
  // NaN was taken as the default (the largest step).
  EXPECT_EQ(message({1e-10, 0.25, "rms", std::nan("")}),
            "--unit-distance: must be positive and finite (0, the default: the largest step)");
  EXPECT_EQ(message({std::nan(""), -1, "median", -1}), "--tol: must be a positive finite number, got nan");
  VerifyOptions o;
  apply({1e-9, 0.5, "p99", 2}, o);
  EXPECT_EQ(o.reference_tol, 1e-9);
  EXPECT_EQ(o.order_tolerance, 0.5);
  EXPECT_EQ(o.order_metric, Metric::p99);
  EXPECT_EQ(o.unit_distance, 2);
}

// An RGB scene's reference channel per image channel: by name (any order, any case, a layer's
// last part), in order when the names do not name three different colours; alpha reads channel 0.
TEST(ReferenceChannels, ByNameElseInOrder) {
  const auto truth = [](std::vector<std::string> names, int alpha = -1) {
    ImageWithStep im{"im.exr", 0.1, ChannelImage(ImageF64(1, 1, 0.0, static_cast<int>(names.size())), names)};
    im.image.alpha = alpha;
    return reference_channels(im, 3);
  };
  EXPECT_EQ(truth({"B", "R", "G"}), (std::vector<int>{2, 0, 1}));
  EXPECT_EQ(truth({"rgba.g", "rgba.b", "rgba.r", "rgba.A"}, 3), (std::vector<int>{1, 2, 0, 0}));
  EXPECT_EQ(truth({"Blue", "Green", "Red"}), (std::vector<int>{2, 1, 0}));
  EXPECT_EQ(truth({"X", "Y", "Z"}), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(truth({"R", "R", "B"}), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(truth({"A", "B", "G", "R"}, 0), (std::vector<int>{0, 2, 1, 0}));
  ImageWithStep grey{"grey.exr", 0.1, ChannelImage(ImageF64(1, 1))};
  EXPECT_EQ(reference_channels(grey, 1), (std::vector<int>{0}));
  EXPECT_THROW(reference_channels(grey, 3), VerifyInputError);
}

// The quantum an in-memory image gets for its pixel type, as a file of that type would.
TEST(StoredQuantum, IsTheTypesStep) {
  EXPECT_EQ(stored_quantum("uint8", 7.0), 1.0 / 255);
  EXPECT_EQ(stored_quantum("uint16", 7.0), 1.0 / 65535);
  EXPECT_EQ(stored_quantum("float", 0.75), std::ldexp(1.0, -24));
  EXPECT_EQ(stored_quantum("double", 1.0), std::ldexp(1.0, -52));
  EXPECT_EQ(stored_quantum("float", 0.0), 0.0);
  EXPECT_THROW(stored_quantum("complex", 1.0), std::invalid_argument);
}

}  // namespace
}  // namespace vrv::verify_toy
