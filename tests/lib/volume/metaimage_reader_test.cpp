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
