// Image headers walked before OpenImageIO reads a file (lib/io/image_structure.h): a PNG chunk or
// EXR attribute claiming more than the file holds is refused in one line naming it (the message is
// the walk's, so libpng and OpenEXR never saw the file), the EXR's attributes stepped over as
// OpenEXR reads them; images vrv writes pass.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "lib/io/image_channels.h"
#include "lib/io/image_io.h"
#include "lib/io/image_structure.h"

namespace vrv {
namespace {

namespace fs = std::filesystem;

// The image fuzzer's inputs: the first byte picks the extension, the rest is the file.
std::string fuzz_input(const char* name) {
  std::ifstream in(fs::path(VRV_SOURCE_DIR) / "tests/fuzz/corpus/image_reader" / name, std::ios::binary);
  return std::string{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()}.substr(1);
}

constexpr const char* kPngProblem =
    "PNG chunk 'tEXt' at byte 292 claims 1627389980 bytes, 327 are left (damaged or truncated)";
constexpr const char* kExrProblem =
    "EXR attribute 'vrv:step' at byte 786 claims 1819239187 bytes, 63 are left (damaged or truncated)";
// Its channel list declares 19 bytes and takes 20: OpenEXR, one byte out of step, reads the text
// "inte" as the next string's size (and allocated 1.7 GB before finding the file's end).
constexpr const char* kExrOutOfStep =
    "EXR attribute ' up [0, 1, 0] fov 40 extent 2.5 angle 0 4x3vrv:method' at byte 323 claims 1702129257 "
    "bytes, 59 are left (damaged or truncated)";

TEST(ImageStructure, AHeaderClaimingMoreThanTheFileIsNamed) {
  const std::string png = fuzz_input("chunk_length_past_end.png");
  ASSERT_EQ(png.size(), 631u);
  EXPECT_EQ(image_structure_problem(png), kPngProblem);
  // Cut inside a chunk's data: named too; cut inside a header: left to libpng.
  EXPECT_NE(image_structure_problem(png.substr(0, 45)).find("'oFFs' at byte 33"), std::string::npos);
  EXPECT_EQ(image_structure_problem(png.substr(0, 36)), "");
  EXPECT_EQ(image_structure_problem(fuzz_input("attribute_length_past_end.exr")), kExrProblem);
  EXPECT_EQ(image_structure_problem(fuzz_input("channel_list_size_wrong.exr")), kExrOutOfStep);
  EXPECT_EQ(image_structure_problem("not an image at all"), "");
}

// The walk steps over an attribute as OpenEXR reads it, whatever size the attribute declares.
TEST(ImageStructure, AnAttributeTakesWhatOpenExrReads) {
  using namespace std::string_literals;
  const std::string channel = "Y\0"s + std::string(16, '\1');  // a name, then type, sampling...
  EXPECT_EQ(exr_value_extent("chlist", channel + "\0"s, 0, 18), 19u);  // the entry and the end
  EXPECT_EQ(exr_value_extent("chlist", "xx" + channel + channel + "\0"s, 2, 0), 37u);
  EXPECT_EQ(exr_value_extent("chlist", channel, 0, 19), std::nullopt);  // no end within the bytes
  EXPECT_EQ(exr_value_extent("box2i", "", 0, 3), 16u);
  EXPECT_EQ(exr_value_extent("compression", "", 0, 1000), 1u);
  EXPECT_EQ(exr_value_extent("tiledesc", "", 0, 0), 9u);
  EXPECT_EQ(exr_value_extent("string", "", 0, 7), 7u);
  EXPECT_EQ(exr_value_extent("floatvector", "", 0, 11), 8u);
  EXPECT_EQ(exr_value_extent("idmanifest", "", 0, 20), 24u);
  EXPECT_EQ(exr_value_extent("someUnknownType", "", 0, 12), 12u);
}

TEST(ImageStructure, TheReaderRefusesItBeforeTheLibraries) {
  const fs::path dir = fs::temp_directory_path() / "vrv_image_structure_test";
  fs::create_directories(dir);
  for (const auto& [name, problem] : {std::pair{"chunk_length_past_end.png", kPngProblem},
                                      std::pair{"attribute_length_past_end.exr", kExrProblem},
                                      std::pair{"channel_list_size_wrong.exr", kExrOutOfStep}}) {
    const fs::path file = dir / name;
    std::ofstream(file, std::ios::binary) << fuzz_input(name);
    try {
      read_channel_image(file);
      ADD_FAILURE() << name << ": read";
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()), file.string() + ": " + problem);
    }
  }
  // What vrv writes (PNG to IEND, EXR with its provenance attributes) passes the walk and reads back.
  const Image image(5, 3, 0.5f);
  write_png_preview(image, dir / "good.png", 0, 1);
  write_exr(image, dir / "good.exr");
  for (const char* name : {"good.png", "good.exr"}) {
    EXPECT_EQ(image_file_structure_problem(dir / name), "") << name;
    EXPECT_EQ(read_channel_image(dir / name).width, 5) << name;
  }
  fs::remove_all(dir);
}

// The walk the reader's check and the image fuzzer's size limit share: every attribute of an EXR
// vrv writes, in order, its dataWindow the image's box (x0, y0, x1, y1) = (0, 0, 4, 2).
TEST(ImageStructure, TheWalkVisitsEveryAttributeAsOpenExrReadsIt) {
  const fs::path file = fs::temp_directory_path() / "vrv_image_structure_walk.exr";
  write_exr(Image(5, 3, 0.5f), file);
  std::ifstream in(file, std::ios::binary);
  const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  fs::remove(file);
  std::vector<std::string> names;
  std::string window;
  walk_exr_attributes(bytes, bytes.size(), [&](const ExrAttribute& a) {
    names.emplace_back(a.name);
    if (a.name == "dataWindow") window = bytes.substr(a.value, 16);
    return true;
  });
  for (const char* required : {"channels", "compression", "dataWindow", "displayWindow", "lineOrder"})
    EXPECT_NE(std::find(names.begin(), names.end(), required), names.end()) << required;
  ASSERT_EQ(window.size(), 16u);
  std::int32_t box[4];
  std::memcpy(box, window.data(), sizeof box);  // little-endian, as this machine
  EXPECT_EQ(box[0], 0);
  EXPECT_EQ(box[1], 0);
  EXPECT_EQ(box[2], 4);
  EXPECT_EQ(box[3], 2);
  // Stopped where the visitor says so; nothing for bytes that are not EXR.
  int visited = 0;
  walk_exr_attributes(bytes, bytes.size(), [&](const ExrAttribute&) { return ++visited < 2; });
  EXPECT_EQ(visited, 2);
  walk_exr_attributes("not an image at all", 19, [&](const ExrAttribute&) { return ++visited, true; });
  EXPECT_EQ(visited, 2);
}

}  // namespace
}  // namespace vrv
