#include "lib/volume/vti_reader.h"

#include <gtest/gtest.h>

#include "tests/lib/volume/volume_fixtures.h"

namespace vrv {
namespace {

Volume vti_volume(const std::filesystem::path& p) { return read_vti(p); }

// ascii, binary and appended raw, each with and without zlib (several blocks), both byte orders,
// UInt32 and UInt64 headers, extents not starting at 0, a mirrored and permuted Direction.
TEST(VtiReader, ReadsEveryFixtureAsWritten) { EXPECT_EQ(test::expect_fixtures("vti_", vti_volume), 11); }

TEST(VtiReader, RefusesBadFilesInOneLine) { EXPECT_EQ(test::expect_bad_fixtures("bad_vti_", vti_volume), 5); }

}  // namespace
}  // namespace vrv
