// verify_images on images of a raycaster that is not vrv's (tests/lib/toy_raycaster.h), written
// to EXR and read back as a user's files would be: the correct one converges at order 2 and
// behaves like vrv's inviwo/alpha model; the planted faults are caught and named.
#include "lib/verify.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "lib/io/image_io.h"
#include "lib/io/atomic_file.h"
#include "lib/io/image_channels.h"
#include "lib/io/npy.h"
#include "lib/io/scene_file.h"
#include "tests/lib/toy_raycaster.h"

namespace vrv {
namespace {

namespace fs = std::filesystem;

constexpr const char* kScene = R"(
[volume]
min = [-1.0, -1.0, -1.0]
max = [1.0, 1.0, 1.0]
[field]
kind = "marschner_lobb"
[transfer]
emission = [[0.0, 0.0], [1.0, 1.0]]
extinction = [[0.0, 0.0], [1.0, 2.0]]
[background]
intensity = 0.2
[camera]
eye = [1.5, 1.0, -4.0]
target = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fov = 40.0
width = 32
height = 32
)";

const std::vector<double> kSteps{0.1, 0.05, 0.025, 0.0125};

fs::path scratch() {
  const fs::path d = fs::path(VRV_BINARY_DIR) / "tests" / "verify_scratch";
  fs::create_directories(d);
  return d;
}

// The toy's images at every step, through EXR files.
std::vector<ImageWithStep> toy_images(const Scene& scene, toy::Fault fault, const std::string& tag) {
  std::vector<ImageWithStep> out;
  for (double h : kSteps) {
    const std::vector<double> v = toy::render(scene, *scene.camera, h, fault, kSteps.front());
    Image im(scene.camera->width, scene.camera->height);
    std::transform(v.begin(), v.end(), im.pixels.begin(), [](double x) { return static_cast<float>(x); });
    const fs::path file = scratch() / (tag + "_" + std::to_string(h) + ".exr");
    write_exr(im, file);
    out.push_back({file.string(), h, read_channel_image(file)});
  }
  return out;
}

VerifyOptions options() {
  VerifyOptions o;
  o.expected_order = 2;
  return o;
}

bool has_fault(const VerifyReport& r, const std::string& name) {
  return std::any_of(r.faults.begin(), r.faults.end(), [&](const Fault& f) { return f.name == name; });
}

class VerifyToy : public ::testing::Test {
 protected:
  Scene scene = parse_scene(kScene, "toy.toml");
};

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
  EXPECT_FALSE(has_fault(r, "half-step offset"));
  EXPECT_FALSE(has_fault(r, "missing opacity correction"));
  EXPECT_EQ(r.reference.missed, 0);
}

TEST_F(VerifyToy, HalfStepOffsetIsCaughtAndNamed) {
  const VerifyReport r = verify_images(scene, toy_images(scene, toy::Fault::half_step_offset, "offset"), options());
  EXPECT_FALSE(r.pass);
  EXPECT_EQ(r.verdict.verdict, Verdict::converges_lower) << r.verdict.reason;
  EXPECT_NEAR(r.orders[0].fit.order, 1, 0.25);
  EXPECT_TRUE(has_fault(r, "half-step offset"));
  EXPECT_FALSE(has_fault(r, "missing opacity correction"));
}

TEST_F(VerifyToy, MissingOpacityCorrectionIsCaughtAndNamed) {
  const VerifyReport r =
      verify_images(scene, toy_images(scene, toy::Fault::missing_opacity_correction, "uncorrected"), options());
  EXPECT_FALSE(r.pass);
  EXPECT_TRUE(r.verdict.verdict == Verdict::diverges || r.verdict.verdict == Verdict::stalls)
      << verdict_name(r.verdict.verdict) << ": " << r.verdict.reason;
  EXPECT_TRUE(has_fault(r, "missing opacity correction"));
  ASSERT_FALSE(r.diagnosis.empty());
  EXPECT_NE(r.diagnosis.front().opacity.find("not corrected"), std::string::npos);
  EXPECT_FALSE(has_fault(r, "half-step offset"));
}

TEST_F(VerifyToy, JitterIsNamed) {
  const VerifyReport r = verify_images(scene, toy_images(scene, toy::Fault::jitter, "jitter"), options());
  EXPECT_TRUE(has_fault(r, "jitter"));
  EXPECT_FALSE(has_fault(r, "half-step offset"));
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
  EXPECT_TRUE(has_fault(r, "error at transfer-function jumps"));
  EXPECT_FALSE(has_fault(r, "first-order border band"));
  EXPECT_NEAR(r.orders[0].fit.order, 1, 0.25);  // a jump inside a step: first order
}

TEST_F(VerifyToy, EightBitImagesStateTheirFloorAndClaimNoOrderBelowIt) {
  std::vector<ImageWithStep> images = toy_images(scene, toy::Fault::none, "eightbit");
  for (ImageWithStep& im : images) {
    for (double& v : im.image.planes[0]) v = std::round(std::clamp(v, 0.0, 1.0) * 255) / 255;
    im.image.quantum = 1.0 / 255;
    im.image.pixel_type = "uint8";
  }
  const VerifyReport r = verify_images(scene, images, options());
  EXPECT_TRUE(r.channels.back().at_floor);
  EXPECT_NEAR(r.channels.back().floor_rms, 1.0 / 255 / std::sqrt(12.0), 1e-15);
  EXPECT_LT(r.orders[0].fit.points, static_cast<int>(images.size()));  // the floor's points are left out
  EXPECT_TRUE(has_fault(r, "quantisation"));
}

// The same 8-bit values saved as a float EXR (as a renderer's framebuffer often is): the floor is
// the integers' 1/255, not the float's ulp, and it is named as quantisation, not as jitter.
TEST_F(VerifyToy, EightBitValuesInAFloatExrAreAQuantisationFloor) {
  std::vector<ImageWithStep> images;
  for (const ImageWithStep& in : toy_images(scene, toy::Fault::none, "eightbit_float")) {
    Image im(in.image.width, in.image.height);
    std::transform(in.image.planes[0].begin(), in.image.planes[0].end(), im.pixels.begin(), [](double v) {
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
  EXPECT_TRUE(has_fault(r, "quantisation"));
  EXPECT_FALSE(has_fault(r, "jitter"));
  // Float values off the grid keep the float's ulp.
  ImageWithStep fine = images.back();
  fine.image.planes[0][0] += 1e-4;
  EXPECT_LT(effective_quantum(fine.image), 1e-6);
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
  EXPECT_EQ(g.at(0, 2, 1), static_cast<double>(grey[5]));

  std::vector<double> rgba(w * h * 4);
  for (std::size_t i = 0; i < rgba.size(); ++i) rgba[i] = 0.01 * static_cast<double>(i);
  write_file_atomically(scratch() / "rgba.npy", npy_bytes(std::span<const double>(rgba), {2, 3, 4}));
  const ChannelImage c = read_channel_image(scratch() / "rgba.npy");
  EXPECT_EQ(c.names, (std::vector<std::string>{"R", "G", "B", "A"}));
  EXPECT_EQ(c.alpha, 3);
  EXPECT_EQ(c.at(2, 1, 1), rgba[(1 * w + 1) * 4 + 2]);
  EXPECT_EQ(c.at(3, 2, 0), rgba[(0 * w + 2) * 4 + 3]);

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
    for (int x = 0; x < w; ++x) EXPECT_EQ(p.at(0, x, y), static_cast<double>(grey[y * w + x])) << x << ", " << y;
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
      ChannelImage im;
      im.width = scene.camera->width, im.height = scene.camera->height;
      im.names = {"R", "G", "B", "A"};
      im.planes = {c, c, c, a};
      im.alpha = 3;
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
    const VerifyReport grey = verify_images(scene, toy_images(scene, toy::Fault::none, "grey"), o);
    EXPECT_NEAR(r.channels.back().alpha ? r.channels[r.channels.size() - 4].all().rms : 0,
                grey.channels.back().all().rms, 1e-6 * grey.channels.back().all().rms + 1e-7);
  }
}

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
  nan[1].image.planes[0][5] = NAN;
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

// Options with an empty reference cache in scratch()/NAME, no diagnosis.
VerifyOptions cached_options(const std::string& name) {
  VerifyOptions o = options();
  o.diagnose = false;
  o.cache_dir = scratch() / name;
  fs::remove_all(o.cache_dir);
  o.scene_text = kScene;
  return o;
}

TEST_F(VerifyToy, ReferenceIsCachedByContent) {
  VerifyOptions o = cached_options("cache");
  const auto images = toy_images(scene, toy::Fault::none, "cache");
  const VerifyReport first = verify_images(scene, images, o);
  const VerifyReport second = verify_images(scene, images, o);
  EXPECT_FALSE(first.reference.from_cache);
  EXPECT_TRUE(second.reference.from_cache);
  EXPECT_EQ(first.reference_image, second.reference_image);
  o.reference_tol = 1e-9;  // another key: rendered again
  EXPECT_FALSE(verify_images(scene, images, o).reference.from_cache);
}

// A cache entry whose values were changed with its key intact flipped the verdict (issue 22): it
// carries a CRC-64 now, and one that fails it (or is cut) is recomputed, said on stderr, never used.
TEST_F(VerifyToy, ADamagedCacheEntryIsRecomputedNeverUsed) {
  const VerifyOptions o = cached_options("damaged_cache");
  const auto images = toy_images(scene, toy::Fault::none, "damaged_cache");
  const VerifyReport first = verify_images(scene, images, o);
  const fs::path file = first.reference.cache_file;
  ASSERT_TRUE(fs::is_regular_file(file));
  const auto damage = [&](auto&& edit) {
    std::string bytes = [&] { std::ifstream in(file, std::ios::binary); std::ostringstream s; s << in.rdbuf(); return s.str(); }();
    edit(bytes);
    std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
    testing::internal::CaptureStderr();
    const VerifyReport again = verify_images(scene, images, o);
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_FALSE(again.reference.from_cache);
    EXPECT_EQ(again.reference_image, first.reference_image);
    return err;
  };
  const std::size_t n = first.reference_image.size();
  EXPECT_EQ(damage([&](std::string& b) { b[b.size() - 8 - 3 * 8 * n + 3] ^= 0x10; }),  // a value's bits
            "vrv: the reference cache " + file.string() + " fails its checksum (changed or damaged); recomputing it\n");
  EXPECT_NE(damage([](std::string& b) { b.resize(b.size() - 9); }).find("is not this reference's"), std::string::npos);
  EXPECT_TRUE(verify_images(scene, images, o).reference.from_cache);  // rewritten whole
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

TEST_F(VerifyToy, RegionsSplitThePixels) {
  VerifyOptions o = options();
  o.diagnose = false;
  const VerifyReport r = verify_images(scene, toy_images(scene, toy::Fault::none, "regions"), o);
  long sum = 0;
  for (const RegionStats& s : r.channels[0].regions)
    if (s.region != "all") sum += s.pixels;
  EXPECT_EQ(sum, r.channels[0].regions[0].pixels);
  EXPECT_GT(r.reference.silhouette_pixels, 0);
  EXPECT_GT(r.reference.hit_pixels, r.reference.silhouette_pixels);
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
  EXPECT_EQ(message({1e-10, 0.25, "rms", -1}), "--unit-distance: must be positive");
  EXPECT_EQ(message({std::nan(""), -1, "median", -1}), "--tol: must be a positive finite number, got nan");
  VerifyOptions o;
  apply({1e-9, 0.5, "p99", 2}, o);
  EXPECT_EQ(o.reference_tol, 1e-9);
  EXPECT_EQ(o.order_tolerance, 0.5);
  EXPECT_EQ(o.order_metric, Metric::p99);
  EXPECT_EQ(o.unit_distance, 2);
}

}  // namespace
}  // namespace vrv
