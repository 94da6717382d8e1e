#include "lib/io/image_io.h"
#include "lib/io/image_module.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <unistd.h>

#include <OpenImageIO/imageio.h>

namespace vrv {
namespace {

namespace fs = std::filesystem;

class ImageIO : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("vrv_test_image_io_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // No writer leaves its temporary behind.
  void expect_no_tmp() const {
    for (const auto& entry : fs::directory_iterator(dir_))
      EXPECT_NE(entry.path().extension(), ".tmp") << entry.path();
  }

  fs::path dir_;
};

struct Read8 {
  int width = 0, height = 0, channels = 0;
  std::vector<unsigned char> bytes;
  std::string description;
};

Read8 read_8bit(const fs::path& path) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) {
    ADD_FAILURE() << "OIIO cannot open " << path << ": " << OIIO::geterror();
    return {};
  }
  const OIIO::ImageSpec& spec = in->spec();
  Read8 r{spec.width, spec.height, spec.nchannels, {}, spec.get_string_attribute("ImageDescription")};
  EXPECT_EQ(spec.format, OIIO::TypeDesc::UINT8);
  r.bytes.resize(static_cast<std::size_t>(r.width) * r.height * r.channels);
  EXPECT_TRUE(in->read_image(0, 0, 0, r.channels, OIIO::TypeDesc::UINT8, r.bytes.data()));
  in->close();
  return r;
}

TEST_F(ImageIO, ExrRoundTripIsBitExact) {
  Image image(7, 5);
  float x = 0.1f;
  for (auto& p : image.pixels) {
    p = x;
    x = x * -1.37f + 1e-3f;
  }
  image.at(0, 0) = std::numeric_limits<float>::denorm_min();
  image.at(1, 0) = std::numeric_limits<float>::max();
  image.at(2, 0) = -0.0f;
  image.at(6, 4) = 1.0f / 3.0f;
  const fs::path path = dir_ / "round.exr";
  write_exr(image, path);
  const Image back = read_exr(path);
  ASSERT_EQ(back.width, 7);
  ASSERT_EQ(back.height, 5);
  ASSERT_EQ(back.pixels.size(), image.pixels.size());
  EXPECT_EQ(std::memcmp(back.pixels.data(), image.pixels.data(), image.pixels.size() * sizeof(float)), 0);
  EXPECT_EQ(back.at(6, 4), 1.0f / 3.0f);  // row 0 is the top, both ways
  expect_no_tmp();

  // One float channel named Y.
  auto in = OIIO::ImageInput::open(path.string());
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().nchannels, 1);
  EXPECT_EQ(in->spec().format, OIIO::TypeDesc::FLOAT);
  EXPECT_EQ(in->spec().channelnames.at(0), "Y");
}

// The module's general interface: the header and metadata alone, or the pixels as doubles.
TEST_F(ImageIO, ModuleReadsHeadersAndDoubles) {
  Image image(3, 2);
  image.pixels = {1, 2, 3, 4, 5, 0.1f};
  const fs::path path = dir_ / "h.exr";
  write_exr(image, path);
  const auto& module = image_module::functions();
  image_module::ReadRequest header_only;
  header_only.pixels = false;
  image_module::ReadResult h;
  ASSERT_EQ(module.read(path.string(), header_only, h), "");
  EXPECT_EQ(h.width, 3);
  EXPECT_EQ(h.height, 2);
  EXPECT_EQ(h.channels, 1);
  EXPECT_EQ(h.format_name, "openexr");
  EXPECT_EQ(h.pixel_type, "float");
  EXPECT_TRUE(h.floating);
  EXPECT_EQ(h.bits, 32);
  EXPECT_TRUE(h.floats.empty());
  bool zip = false;
  for (const auto& [key, value] : h.attributes) zip |= key == "compression" && value == "zip";
  EXPECT_TRUE(zip);

  image_module::ReadRequest as_double;
  as_double.type = image_module::PixelType::float64;
  image_module::ReadResult d;
  ASSERT_EQ(module.read(path.string(), as_double, d), "");
  ASSERT_EQ(d.doubles.size(), 6u);
  EXPECT_EQ(d.doubles[5], static_cast<double>(0.1f));

  image_module::ReadRequest small;
  small.max_side = 2;
  image_module::ReadResult refused;
  EXPECT_EQ(module.read(path.string(), small, refused), "bad image size 3 x 2");
  EXPECT_TRUE(refused.floats.empty());
}

TEST_F(ImageIO, ExrOverwritesAtomically) {
  const fs::path path = dir_ / "over.exr";
  write_exr(Image(2, 2, 1.0f), path);
  write_exr(Image(3, 1, 2.0f), path);
  const Image back = read_exr(path);
  EXPECT_EQ(back.width, 3);
  EXPECT_EQ(back.at(2, 0), 2.0f);
  expect_no_tmp();
}

TEST_F(ImageIO, PngPreviewScalesAndClamps) {
  Image image(4, 3, 0.5f);
  image.at(0, 0) = 5.0f;   // above hi: 255
  image.at(1, 0) = 2.0f;   // (2 - 1) / (3 - 1) = 0.5: round(127.5) = 128
  image.at(3, 2) = 1.25f;  // (1.25 - 1) / (3 - 1) = 0.125: round(31.875) = 32
  image.at(1, 1) = -7.0f;  // below lo: 0
  const fs::path path = dir_ / "preview.png";
  write_png_preview(image, path, 1.0, 3.0);
  Read8 r = read_8bit(path);
  ASSERT_EQ(r.width, 4);
  ASSERT_EQ(r.height, 3);
  ASSERT_EQ(r.channels, 1);
  EXPECT_EQ(r.bytes[0], 255);
  EXPECT_EQ(r.bytes[1], 128);
  EXPECT_EQ(r.bytes[4], 0);  // 0.5 is below lo
  EXPECT_EQ(r.bytes[2 * 4 + 3], 32);
  EXPECT_EQ(r.bytes[1 * 4 + 1], 0);
  expect_no_tmp();
}

TEST_F(ImageIO, PngPreviewNeedsARange) {
  EXPECT_THROW(write_png_preview(Image(1, 1), dir_ / "p.png", 1, 1), std::invalid_argument);
  EXPECT_FALSE(fs::exists(dir_ / "p.png"));
}

TEST_F(ImageIO, ErrorMapIsRgbWithColourBar) {
  Image error(6, 5, 0.0f);
  error.at(0, 0) = 0.5f;    // +max: red
  error.at(1, 0) = -0.5f;   // -max: blue
  error.at(2, 0) = 0.25f;   // halfway to red
  error.at(3, 0) = -2.0f;   // beyond the range: clamped to blue
  const fs::path path = dir_ / "error.png";
  write_error_map_png(error, path, 0.5);
  Read8 r = read_8bit(path);
  ASSERT_EQ(r.channels, 3);
  ASSERT_EQ(r.width, 6 + kErrorBarGap + kErrorBarWidth);
  ASSERT_EQ(r.height, 5);
  auto px = [&](int x, int y) {
    const unsigned char* p = &r.bytes[(static_cast<std::size_t>(y) * r.width + x) * 3];
    return Rgb8{p[0], p[1], p[2]};
  };
  auto expect_rgb = [&](int x, int y, Rgb8 want) {
    const Rgb8 got = px(x, y);
    EXPECT_EQ(got.r, want.r) << x << "," << y;
    EXPECT_EQ(got.g, want.g) << x << "," << y;
    EXPECT_EQ(got.b, want.b) << x << "," << y;
  };
  const Rgb8 red{178, 24, 43}, blue{33, 102, 172}, white{255, 255, 255};
  expect_rgb(0, 0, red);
  expect_rgb(1, 0, blue);
  expect_rgb(2, 0, {217, 140, 149});  // white + (red - white) / 2, rounded
  expect_rgb(3, 0, blue);
  expect_rgb(4, 4, white);
  // The gap is black; the bar runs from red (top) through white (middle) to blue (bottom).
  for (int y = 0; y < 5; ++y)
    for (int x = 6; x < 6 + kErrorBarGap; ++x) expect_rgb(x, y, {0, 0, 0});
  for (int x = 6 + kErrorBarGap; x < r.width; ++x) {
    expect_rgb(x, 0, red);
    expect_rgb(x, 2, white);
    expect_rgb(x, 4, blue);
  }
  EXPECT_NE(r.description.find("0.5"), std::string::npos) << r.description;
  expect_no_tmp();
}

TEST_F(ImageIO, DivergingColourMap) {
  EXPECT_EQ(diverging_colour(0, 1).g, 255);
  EXPECT_EQ(diverging_colour(1, 0).r, 255);  // no range: white
  const Rgb8 nan = diverging_colour(NAN, 1);
  EXPECT_EQ(nan.r + nan.g + nan.b, 0);
  EXPECT_GT(diverging_colour(0.3, 1).r, diverging_colour(0.3, 1).b);
  EXPECT_LT(diverging_colour(-0.3, 1).r, diverging_colour(-0.3, 1).b);
}

TEST_F(ImageIO, WritingIntoAMissingDirectoryThrowsNamingThePath) {
  const fs::path path = dir_ / "no_such_dir" / "x.exr";
  for (int kind = 0; kind < 3; ++kind) {
    try {
      if (kind == 0) write_exr(Image(2, 2), path);
      if (kind == 1) write_png_preview(Image(2, 2), path, 0, 1);
      if (kind == 2) write_error_map_png(Image(2, 2), path, 1);
      ADD_FAILURE() << "no error for kind " << kind;
    } catch (const std::runtime_error& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.rfind(path.string() + ": ", 0), 0u) << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
  }
  EXPECT_FALSE(fs::exists(dir_ / "no_such_dir"));
  expect_no_tmp();
}

TEST_F(ImageIO, ReadErrorsNameTheFile) {
  const fs::path missing = dir_ / "missing.exr";
  try {
    read_exr(missing);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(missing.string() + ": ", 0), 0u) << e.what();
  }
  // Not an image.
  const fs::path junk = dir_ / "junk.exr";
  { std::ofstream(junk) << "not an image\n"; }
  try {
    read_exr(junk);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(junk.string() + ": ", 0), 0u) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
  }
  // Three channels are not a one-channel image.
  const fs::path rgb = dir_ / "rgb.png";
  write_error_map_png(Image(2, 2), rgb, 1);
  try {
    read_exr(rgb);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("channel"), std::string::npos) << e.what();
  }
}

TEST_F(ImageIO, BadImageSizeThrows) {
  Image image(3, 3);
  image.pixels.pop_back();
  EXPECT_THROW(write_exr(image, dir_ / "bad.exr"), std::runtime_error);
  EXPECT_FALSE(fs::exists(dir_ / "bad.exr"));
}

}  // namespace
}  // namespace vrv
