// verify_images end to end on images of a raycaster that is not vrv's (tests/lib/toy_raycaster.h),
// written to EXR and read back as a user's files would be: the correct one converges at order 2 and
// behaves like vrv's inviwo/alpha model, RGBA images premultiplied or straight, a reference that
// misses its tolerance fails; and the image formats renderers write.  The parts' own tests are in
// tests/lib/verify/.
#include <cmath>
#include <filesystem>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "lib/io/atomic_file.h"
#include "lib/io/npy.h"
#include "lib/work_estimate.h"
#include "tests/lib/verify/verify_toy.h"

namespace vrv::verify_toy {
namespace {

namespace fs = std::filesystem;

TEST_F(VerifyToy, CorrectRendererConvergesAtOrderTwoAndIsNamed) {
  const VerifyReport r = verify_images(scene, toy_images(scene, toy::Fault::none, "correct"), options());
  EXPECT_TRUE(r.pass) << r.verdict.reason;
  EXPECT_EQ(r.verdict.verdict, Verdict::converges) << r.verdict.reason;
  // Against the reference and from successive differences alone (no reference): the coarsest
  // step is still pre-asymptotic (local orders 2.6, 2.2, 2.1), so the fits lie a little above 2.
  const auto& ref = r.orders[0];
  EXPECT_GE(ref.fit.order, 1.75);
  EXPECT_LE(ref.fit.order, 2.5);
  EXPECT_NEAR(std::log(ref.errors[2] / ref.errors[3]) / std::log(2.0), 2, 0.15) << to_json(r)["orders"].dump();
  EXPECT_GE(r.orders[1].fit.order, 1.75);
  EXPECT_LE(r.orders[1].fit.order, 2.75);
  ASSERT_FALSE(r.diagnosis.empty());
  EXPECT_EQ(r.diagnosis.front().placement, "inviwo");
  EXPECT_EQ(r.diagnosis.front().rule, "alpha");
  EXPECT_LT(r.diagnosis.front().rms, 1e-6);  // the same sums up to float storage and rounding
  EXPECT_FALSE(has_fault(r, FaultKind::half_step_offset));
  EXPECT_FALSE(has_fault(r, FaultKind::missing_opacity_correction));
  EXPECT_EQ(r.reference.missed, 0);
}

// RGBA over nothing, premultiplied or straight: each colour channel composited over the
// background matches the grey image's errors, and alpha converges to the reference opacity.
TEST_F(VerifyToy, RgbaPremultipliedAndStraight) {
  for (AlphaMode mode : {AlphaMode::premultiplied, AlphaMode::straight}) {
    std::vector<ImageWithStep> images;
    for (double h : kSteps) {
      std::vector<double> a;
      std::vector<double> c = toy::render(scene, *scene.camera, h, toy::Fault::none, h, &a);
      if (mode == AlphaMode::straight)
        for (std::size_t i = 0; i < c.size(); ++i) c[i] = a[i] > 0 ? c[i] / a[i] : 0;
      ChannelImage im = planar_image(scene.camera->width, scene.camera->height, {c, c, c, a}, {"R", "G", "B", "A"});
      ASSERT_EQ(im.alpha, 3);
      im.pixel_type = "double";
      images.push_back({"rgba " + std::to_string(h), h, im});
    }
    VerifyOptions o = options();
    o.alpha = mode;
    o.diagnose = false;
    const VerifyReport r = verify_images(scene, images, o);
    EXPECT_TRUE(r.pass) << r.verdict.reason;
    ASSERT_EQ(r.orders.size(), 8u);  // R, G, B, A: reference and self each
    EXPECT_EQ(r.orders[6].channel, "A");
    EXPECT_GE(r.orders[6].fit.order, 1.75);
    // The colour channels' errors equal the grey image's (the same numbers composited here).
    VerifyOptions grey_options = o;
    grey_options.alpha = AlphaMode::as_stored;  // the grey images have no alpha for it to read
    const VerifyReport grey = verify_images(scene, toy_images(scene, toy::Fault::none, "grey"), grey_options);
    EXPECT_NEAR(r.channels.back().alpha ? r.channels[r.channels.size() - 4].all().rms : 0,
                grey.channels.back().all().rms, 1e-6 * grey.channels.back().all().rms + 1e-7);
  }
}

TEST_F(VerifyToy, AReferenceThatMissesItsToleranceFailsNamingPixels) {
  VerifyOptions o = options();
  o.diagnose = false;
  o.reference_tol = 1e-19;  // below what double arithmetic can certify
  const VerifyReport r = verify_images(scene, toy_images(scene, toy::Fault::none, "tol"), o);
  EXPECT_FALSE(r.pass);
  EXPECT_GT(r.reference.missed, 0);
  ASSERT_FALSE(r.failures.empty());
  EXPECT_NE(r.failures.front().find("misses its tolerance"), std::string::npos) << r.failures.front();
  EXPECT_NE(r.failures.front().find(fmt::format("({}, {})", r.reference.missed_pixels[0].first,
                                                r.reference.missed_pixels[0].second)), std::string::npos);
}

// Images as renderers write them: numpy.save's .npy (2-D float32, H x W x 4 float64) read by hand,
// PFM through OpenImageIO (stored bottom row first: read back top row first), with their values.
TEST(ImageFormats, NpyAndPfmAreReadAsTheRendererWroteThem) {
  const int w = 3, h = 2;
  std::vector<float> grey(w * h);
  for (int i = 0; i < w * h; ++i) grey[i] = 0.1f * static_cast<float>(i) + 0.05f;
  write_file_atomically(scratch() / "grey.npy", npy_bytes(std::span<const float>(grey), {2, 3}));
  const ChannelImage g = read_channel_image(scratch() / "grey.npy");
  ASSERT_EQ(g.width, w);
  ASSERT_EQ(g.height, h);
  EXPECT_EQ(g.names, std::vector<std::string>{"Y"});
  EXPECT_EQ(g.pixel_type, "float");
  EXPECT_EQ(g.value(1 * w + 2, 0), static_cast<double>(grey[5]));

  std::vector<double> rgba(w * h * 4);
  for (std::size_t i = 0; i < rgba.size(); ++i) rgba[i] = 0.01 * static_cast<double>(i);
  write_file_atomically(scratch() / "rgba.npy", npy_bytes(std::span<const double>(rgba), {2, 3, 4}));
  const ChannelImage c = read_channel_image(scratch() / "rgba.npy");
  EXPECT_EQ(c.names, (std::vector<std::string>{"R", "G", "B", "A"}));
  EXPECT_EQ(c.alpha, 3);
  EXPECT_EQ(c.value(1 * w + 1, 2), rgba[(1 * w + 1) * 4 + 2]);
  EXPECT_EQ(c.value(0 * w + 2, 3), rgba[(0 * w + 2) * 4 + 3]);

  write_file_atomically(scratch() / "five.npy", npy_bytes(std::span<const double>(rgba), {2, 3, 2, 2}));
  EXPECT_THROW(read_channel_image(scratch() / "five.npy"), std::runtime_error);

  // PFM: "Pf" (grey), width height, -1 (little-endian), rows from the bottom.
  std::string pfm = fmt::format("Pf\n{} {}\n-1.0\n", w, h);
  for (int y = h - 1; y >= 0; --y)
    for (int x = 0; x < w; ++x) pfm.append(reinterpret_cast<const char*>(&grey[y * w + x]), sizeof(float));
  write_file_atomically(scratch() / "grey.pfm", pfm);
  const ChannelImage p = read_channel_image(scratch() / "grey.pfm");
  ASSERT_EQ(p.width, w);
  ASSERT_EQ(p.height, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) EXPECT_EQ(p.at(x, y), static_cast<double>(grey[y * w + x])) << x << ", " << y;
}

// What --max-work compares (issue 22): the reference on every pixel and the diagnosis' casts,
// which a fine step makes the larger part; without the diagnosis only the reference.
TEST_F(VerifyToy, TheWorkEstimateCountsTheDiagnosis) {
  VerifyOptions o = options();
  const Camera camera = verify_camera(scene, o, 32, 32);
  const VerificationWork work = verification_work(scene, o, 32, 32, kSteps);
  EXPECT_EQ(work.reference, camera_work(scene, camera, o.reference_tol));
  EXPECT_EQ(work.diagnosis, diagnosis_work(scene, camera, kSteps, o));
  EXPECT_EQ(work.total(), work.reference + work.diagnosis);
  const VerificationWork fine = verification_work(scene, o, 32, 32, {1e-4, 5e-5});
  EXPECT_GT(fine.diagnosis, 100 * fine.reference);
  o.diagnose = false;
  EXPECT_EQ(verification_work(scene, o, 32, 32, kSteps).diagnosis, 0);
}

}  // namespace
}  // namespace vrv::verify_toy
