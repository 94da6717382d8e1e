#include "lib/volume/nrrd_reader.h"

#include <gtest/gtest.h>

#include "tests/lib/volume/volume_fixtures.h"

namespace vrv {
namespace {

Volume read_nrrd_file(const std::filesystem::path& p) { return read_nrrd(p); }

// Eight types in both byte orders, gzip, a mirrored and permuted placement, a detached header:
// as make_volume_fixtures.py wrote them.
TEST(NrrdReader, ReadsEveryFixtureAsWritten) { EXPECT_EQ(test::expect_fixtures("nrrd_", read_nrrd_file), 17); }

TEST(NrrdReader, RefusesBadFilesInOneLine) { EXPECT_EQ(test::expect_bad_fixtures("bad_nrrd_", read_nrrd_file), 4); }

TEST(NrrdReader, TheDetachedDataFileIsOneOfTheVolumesFiles) {
  const Volume v = read_nrrd(test::volume_fixture_dir() / "nrrd_u16_detached.nhdr");
  ASSERT_EQ(v.files.size(), 2u);
  EXPECT_EQ(v.files[1], test::volume_fixture_dir() / "nrrd_u16_detached.raw");
}

TEST(NrrdReader, RefusesAVolumeAboveTheBudgetBeforeReadingIt) {
  const auto path = test::volume_fixture_dir() / "nrrd_f64_little.nrrd";
  try {
    read_nrrd(path, {100});
    FAIL() << "read";
  } catch (const VolumeFileError& e) {
    EXPECT_EQ(std::string(e.what()), path.string() + ": sizes: 5 x 4 x 3 float64 samples take 480 bytes, more "
                                                     "than the 100 allowed (--max-memory)");
  }
}

TEST(NrrdReader, AMissingFileIsOneLine) {
  EXPECT_THROW(read_nrrd("/nonexistent/x.nrrd"), VolumeFileError);
  try {
    read_volume("/nonexistent/x.nrrd");
  } catch (const VolumeFileError& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent/x.nrrd: (file): cannot open: No such file or directory");
  }
}

}  // namespace
}  // namespace vrv

namespace vrv {
namespace {

// Only NRRD: Teem's other formats (here a PNM) are not tried (their failure paths leak in Teem).
TEST(NrrdReader, RefusesAFileWithoutTheNrrdMagic) {
  const auto path = std::filesystem::temp_directory_path() / "vrv_nrrd_reader_pnm.nrrd";
  std::ofstream(path, std::ios::binary) << "P5\n2 2\n255\nabcd";
  try {
    read_nrrd(path);
    ADD_FAILURE() << "read";
  } catch (const VolumeFileError& e) {
    EXPECT_EQ(std::string(e.what()), path.string() + ": (header): not a NRRD file (no NRRD000x magic on its first line)");
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace vrv

namespace vrv {
namespace {

// Data read straight from the file (raw and gzip of one data file) honour the header's line and
// byte skips; what only Teem reads (ascii, a byte skip inside gzip) still reads the same values.
std::filesystem::path write_file(const std::string& name, const std::string& bytes) {
  const auto path = std::filesystem::temp_directory_path() / name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

std::string u16_big(const std::vector<int>& values) {
  std::string s;
  for (int v : values) s += static_cast<char>(v >> 8), s += static_cast<char>(v & 0xff);
  return s;
}

const std::vector<int> kValues{0, 1, 256, 257, 65535, 4660, 7, 8};  // 2 x 2 x 2

void expect_values(const Volume& v) {
  ASSERT_EQ(v.count(), kValues.size());
  for (std::size_t n = 0; n < kValues.size(); ++n) EXPECT_EQ(v.sample(n), kValues[n]) << n;
}

std::string header(const std::string& encoding, const std::string& extra) {
  return "NRRD0004\ntype: uint16\ndimension: 3\nsizes: 2 2 2\nendian: big\nencoding: " + encoding + "\n" + extra;
}

TEST(NrrdReader, DetachedRawDataHonourTheLineAndByteSkips) {
  write_file("vrv_nrrd_skip.raw", "junk line\nmore\nABCDE" + u16_big(kValues));
  const auto nhdr = write_file("vrv_nrrd_skip.nhdr", header("raw", "line skip: 2\nbyte skip: 5\ndata file: vrv_nrrd_skip.raw\n"));
  expect_values(read_nrrd(nhdr));
}

TEST(NrrdReader, AttachedRawDataHonourTheByteSkip) {
  expect_values(read_nrrd(write_file("vrv_nrrd_byteskip.nrrd", header("raw", "byte skip: 3\n") + "\nxyz" + u16_big(kValues))));
}

TEST(NrrdReader, AsciiDataGoThroughTeem) {
  std::string text;
  for (int v : kValues) text += std::to_string(v) + " ";
  expect_values(read_nrrd(write_file("vrv_nrrd_ascii.nrrd", header("ascii", "") + "\n" + text + "\n")));
}

TEST(NrrdReader, TruncatedDetachedRawDataAreOneLine) {
  write_file("vrv_nrrd_short.raw", u16_big(kValues).substr(0, 11));
  const auto nhdr = write_file("vrv_nrrd_short.nhdr", header("raw", "data file: vrv_nrrd_short.raw\n"));
  try {
    read_nrrd(nhdr);
    ADD_FAILURE() << "read";
  } catch (const VolumeFileError& e) {
    EXPECT_EQ(std::string(e.what()), nhdr.string() + ": (data): truncated: 11 bytes of data where 8 uint16 samples need 16");
  }
}

}  // namespace
}  // namespace vrv
