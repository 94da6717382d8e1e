#include "lib/volume/metaimage_reader.h"

#include <gtest/gtest.h>

#include "tests/lib/volume/volume_fixtures.h"

namespace vrv {
namespace {

Volume read(const std::filesystem::path& p) { return read_metaimage(p); }

// Eight types in both byte orders, zlib, TransformMatrix with mirrored and permuted axes, .mhd.
TEST(MetaImageReader, ReadsEveryFixtureAsWritten) {
  EXPECT_EQ(test::expect_fixtures("mha_", read) + test::expect_fixtures("mhd_", read), 17);
}

TEST(MetaImageReader, RefusesBadFilesInOneLine) { EXPECT_EQ(test::expect_bad_fixtures("bad_mha_", read), 5); }

TEST(MetaImageReader, TheDetachedDataFileIsOneOfTheVolumesFiles) {
  const Volume v = read_metaimage(test::volume_fixture_dir() / "mhd_u16.mhd");
  ASSERT_EQ(v.files.size(), 2u);
  EXPECT_EQ(v.files[1].filename(), "mhd_u16.raw");
}

}  // namespace
}  // namespace vrv

namespace vrv {
namespace {

// A missing data file is named from the header that points at it (found by fuzz_metaimage_reader).
TEST(MetaImageReader, AMissingDataFileIsNamedFromTheHeader) {
  const auto path = std::filesystem::temp_directory_path() / "vrv_metaimage_missing.mhd";
  std::ofstream(path) << "NDims = 3\nDimSize = 2 2 2\nElementType = MET_UCHAR\nElementDataFile = none.raw\n";
  try {
    read_metaimage(path);
    ADD_FAILURE() << "read";
  } catch (const VolumeFileError& e) {
    const std::string data = (path.parent_path() / "none.raw").string();
    EXPECT_EQ(std::string(e.what()), path.string() + ": ElementDataFile: " + data + ": (file): cannot open: No such file or directory");
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace vrv
