// Images a verification can trust: double precision beside the float EXR, provenance in the
// metadata of every format vrv render writes.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <limits>

#include "lib/io/image_io.h"

namespace vrv {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::path(VRV_BINARY_DIR) / "image_provenance_test";
  fs::create_directories(dir);
  return dir / name;
}

ImageProvenance sample_provenance() {
  return {"0123456789abcdef0123456789abcdef01234567", "perspective eye 0x0p+0 ...", "alpha step h=0.01 double", 0.01};
}

TEST(ImageProvenance, Float64TiffKeepsEveryDoubleBitForBit) {
  ImageF64 im{3, 2, {0.1, 1.0 / 3, 1 + std::numeric_limits<double>::epsilon(), -0.0, 1e-300, 0.8006225323695293}};
  const fs::path path = scratch("values.f64.tiff");
  write_tiff_f64(im, path);
  const ImageF64 back = read_image_f64(path);
  ASSERT_EQ(back.width, 3);
  ASSERT_EQ(back.height, 2);
  for (std::size_t i = 0; i < im.pixels.size(); ++i) EXPECT_EQ(back.pixels[i], im.pixels[i]) << i;
  const ImageInfo info = read_image_info(path);
  EXPECT_TRUE(info.floating);
  EXPECT_EQ(info.bits, 64);
  EXPECT_EQ(info.pixel_type, "double");
  // The float EXR cannot tell 1 from 1 + eps; the TIFF can.
  EXPECT_NE(back.pixels[2], 1.0);
}

TEST(ImageProvenance, EveryWrittenFormatCarriesIt) {
  const ImageProvenance p = sample_provenance();
  Image im(4, 3, 0.25f);
  const fs::path exr = scratch("p.exr"), png = scratch("p.png"), tif = scratch("p.f64.tiff");
  write_exr(im, exr, &p);
  write_png_preview(im, png, 0, 1, &p);
  write_tiff_f64(ImageF64{4, 3, std::vector<double>(12, 0.25)}, tif, &p);
  for (const fs::path& path : {exr, png, tif}) {
    const auto back = read_provenance(path);
    ASSERT_TRUE(back) << path;
    EXPECT_EQ(back->scene_hash, p.scene_hash) << path;
    EXPECT_EQ(back->camera, p.camera) << path;
    EXPECT_EQ(back->method, p.method) << path;
    ASSERT_TRUE(back->step) << path;
    EXPECT_EQ(*back->step, 0.01) << path;
  }
  EXPECT_FALSE(read_image_info(png).floating);
  EXPECT_EQ(read_image_info(png).bits, 8);
}

// The image fuzzer's find: a damaged vrv:step attribute ended the process through std::stod's
// exception; it is refused in one line naming the file and the attribute.
TEST(ImageProvenance, ADamagedStepIsRefusedInOneLine) {
  std::ifstream in(fs::path(VRV_SOURCE_DIR) / "tests/fuzz/corpus/image_reader/provenance_step_not_a_number.exr",
                   std::ios::binary);
  const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  const fs::path path = scratch("bad_step.exr");
  std::ofstream(path, std::ios::binary) << bytes.substr(1);  // the fuzzer's first byte picks the extension
  try {
    read_provenance(path);
    ADD_FAILURE() << "read";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(path.string() + ": vrv:step: must be a positive number, got '", 0), 0u) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos);
  }
}

TEST(ImageProvenance, AnImageWithoutItHasNone) {
  const fs::path exr = scratch("plain.exr");
  write_exr(Image(2, 2), exr);
  EXPECT_FALSE(read_provenance(exr));
  EXPECT_THROW(read_provenance(scratch("missing.exr")), std::runtime_error);
}

}  // namespace
}  // namespace vrv
