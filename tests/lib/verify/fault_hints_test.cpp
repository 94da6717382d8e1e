// lib/verify/fault_hints: faults planted in the toy renderer are caught and named, and only they.
#include <cmath>
#include <filesystem>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "tests/lib/verify/verify_toy.h"

namespace vrv::verify_toy {
namespace {

namespace fs = std::filesystem;

TEST_F(VerifyToy, HalfStepOffsetIsCaughtAndNamed) {
  const VerifyReport r = verify_images(scene, toy_images(scene, toy::Fault::half_step_offset, "offset"), options());
  EXPECT_FALSE(r.pass);
  EXPECT_EQ(r.verdict.verdict, Verdict::converges_lower) << r.verdict.reason;
  EXPECT_NEAR(r.orders[0].fit.order, 1, 0.25);
  EXPECT_TRUE(has_fault(r, FaultKind::half_step_offset));
  EXPECT_FALSE(has_fault(r, FaultKind::missing_opacity_correction));
}

TEST_F(VerifyToy, MissingOpacityCorrectionIsCaughtAndNamed) {
  const VerifyReport r =
      verify_images(scene, toy_images(scene, toy::Fault::missing_opacity_correction, "uncorrected"), options());
  EXPECT_FALSE(r.pass);
  EXPECT_TRUE(r.verdict.verdict == Verdict::diverges || r.verdict.verdict == Verdict::stalls)
      << verdict_name(r.verdict.verdict) << ": " << r.verdict.reason;
  EXPECT_TRUE(has_fault(r, FaultKind::missing_opacity_correction));
  ASSERT_FALSE(r.diagnosis.empty());
  EXPECT_FALSE(r.diagnosis.front().opacity_corrected) << r.diagnosis.front().name;
  EXPECT_FALSE(has_fault(r, FaultKind::half_step_offset));
}

TEST_F(VerifyToy, JitterIsNamed) {
  const VerifyReport r = verify_images(scene, toy_images(scene, toy::Fault::jitter, "jitter"), options());
  EXPECT_TRUE(has_fault(r, FaultKind::jitter));
  EXPECT_FALSE(has_fault(r, FaultKind::half_step_offset));
}

TEST_F(VerifyToy, ErrorAtTransferFunctionJumpsIsNamed) {
  std::string text = kScene;
  const std::string from = "emission = [[0.0, 0.0], [1.0, 1.0]]\nextinction = [[0.0, 0.0], [1.0, 2.0]]";
  text.replace(text.find(from), from.size(),
               "emission = [[0.0, 0.2], [0.55, 0.2], [0.55, 1.0], [1.0, 1.0]]\n"
               "extinction = [[0.0, 0.5], [0.55, 0.5], [0.55, 2.0], [1.0, 2.0]]");
  const Scene steps = parse_scene(text, "jump.toml");
  VerifyOptions o;
  o.diagnose = false;
  const VerifyReport r = verify_images(steps, toy_images(steps, toy::Fault::none, "jump"), o);
  EXPECT_GT(r.reference.jump_pixels, 0);
  EXPECT_TRUE(has_fault(r, FaultKind::error_at_tf_jumps));
  EXPECT_FALSE(has_fault(r, FaultKind::first_order_border_band));
  EXPECT_NEAR(r.orders[0].fit.order, 1, 0.25);  // a jump inside a step: first order
}

TEST_F(VerifyToy, EightBitImagesStateTheirFloorAndClaimNoOrderBelowIt) {
  std::vector<ImageWithStep> images = toy_images(scene, toy::Fault::none, "eightbit");
  for (ImageWithStep& im : images) {
    for (double& v : im.image.pixels) v = std::round(std::clamp(v, 0.0, 1.0) * 255) / 255;
    im.image.quantum = 1.0 / 255;
    im.image.pixel_type = "uint8";
  }
  const VerifyReport r = verify_images(scene, images, options());
  EXPECT_TRUE(r.channels.back().at_floor);
  EXPECT_NEAR(r.channels.back().floor_rms, 1.0 / 255 / std::sqrt(12.0), 1e-15);
  EXPECT_LT(r.orders[0].fit.points, static_cast<int>(images.size()));  // the floor's points are left out
  EXPECT_TRUE(has_fault(r, FaultKind::quantisation));
}

// The same 8-bit values saved as a float EXR (as a renderer's framebuffer often is): the floor is
// the integers' 1/255, not the float's ulp, and it is named as quantisation, not as jitter.
TEST_F(VerifyToy, EightBitValuesInAFloatExrAreAQuantisationFloor) {
  std::vector<ImageWithStep> images;
  for (const ImageWithStep& in : toy_images(scene, toy::Fault::none, "eightbit_float")) {
    Image im(in.image.width, in.image.height);
    std::transform(in.image.pixels.begin(), in.image.pixels.end(), im.pixels.begin(), [](double v) {
      return static_cast<float>(std::round(std::clamp(v, 0.0, 1.0) * 255) / 255);
    });
    const fs::path file = scratch() / fmt::format("eightbit_float_{}.exr", in.step);
    write_exr(im, file);
    images.push_back({file.string(), in.step, read_channel_image(file)});
    ASSERT_EQ(images.back().image.pixel_type, "float");
  }
  const VerifyReport r = verify_images(scene, images, options());
  EXPECT_DOUBLE_EQ(r.channels.back().quantum, 1.0 / 255);
  EXPECT_TRUE(r.channels.back().at_floor);
  EXPECT_TRUE(has_fault(r, FaultKind::quantisation));
  EXPECT_FALSE(has_fault(r, FaultKind::jitter));
  // Float values off the grid keep the float's ulp.
  ImageWithStep fine = images.back();
  fine.image.pixels[0] += 1e-4;
  EXPECT_LT(effective_quantum(fine.image), 1e-6);
}

}  // namespace
}  // namespace vrv::verify_toy
