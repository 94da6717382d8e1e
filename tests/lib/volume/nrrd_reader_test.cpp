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
