#include "lib/volume/metaimage_reader.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include <unistd.h>
#include <zlib.h>

#include "tests/lib/volume/volume_fixtures.h"

namespace vrv {
namespace {

Volume read_mha(const std::filesystem::path& p) { return read_metaimage(p); }

// Eight types in both byte orders, zlib, TransformMatrix with mirrored and permuted axes, .mhd.
TEST(MetaImageReader, ReadsEveryFixtureAsWritten) {
  EXPECT_EQ(test::expect_fixtures("mha_", read_mha) + test::expect_fixtures("mhd_", read_mha), 17);
}

TEST(MetaImageReader, RefusesBadFilesInOneLine) { EXPECT_EQ(test::expect_bad_fixtures("bad_mha_", read_mha), 5); }

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

namespace vrv {
namespace {

// A header volume.mhd and its data file volume.raw in a folder of the running test's own (ctest
// runs tests in parallel: a shared name had one test read the other's files), removed after.
struct MetaImageTempFiles {
  std::filesystem::path dir = std::filesystem::temp_directory_path() /
                              ("vrv_metaimage_" + std::string(testing::UnitTest::GetInstance()->current_test_info()->name()) +
                               "_" + std::to_string(::getpid()));
  std::filesystem::path header = dir / "volume.mhd";
  std::filesystem::path data = dir / "volume.raw";
  MetaImageTempFiles(const std::string& head, const std::string& bytes) {
    std::filesystem::create_directories(dir);
    std::ofstream(header, std::ios::binary) << head;
    std::ofstream(data, std::ios::binary) << bytes;
  }
  ~MetaImageTempFiles() {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
};

const std::string kMetaImageEightSamples = "NDims = 3\nDimSize = 2 2 2\nElementType = MET_UCHAR\n";

// The samples are read straight from where the header puts them: after HeaderSize bytes, or
// (HeaderSize = -1) at the end of the data file, whatever precedes them.
TEST(MetaImageReader, ReadsTheDataWhereHeaderSizePutsThem) {
  for (const auto& [skip, prefix] : {std::pair{"5", "junk!"}, std::pair{"-1", "any length of junk"}}) {
    SCOPED_TRACE(skip);
    MetaImageTempFiles t(kMetaImageEightSamples + "HeaderSize = " + skip + "\nElementDataFile = volume.raw\n",
               std::string(prefix) + "\x01\x02\x03\x04\x05\x06\x07\x08");
    const Volume v = read_metaimage(t.header);
    ASSERT_EQ(v.count(), 8u);
    for (std::size_t n = 0; n < 8; ++n) EXPECT_EQ(v.sample(n), n + 1.0);
  }
}

// A compressed stream is refused, naming the key, when it is too short for any deflate stream to
// inflate to the samples the header claims (1032:1 at most): before the samples are allocated.
TEST(MetaImageReader, RefusesCompressedDataThatCannotHoldTheClaimedSamples) {
  MetaImageTempFiles t("NDims = 3\nDimSize = 1000 1000 100\nElementType = MET_UCHAR\nCompressedData = True\n"
             "ElementDataFile = volume.raw\n",
             std::string(16, 'x'));
  try {
    read_metaimage(t.header);
    ADD_FAILURE() << "read";
  } catch (const VolumeFileError& e) {
    EXPECT_EQ(std::string(e.what()), t.header.string() +
                                         ": CompressedData: 16 bytes of compressed data cannot inflate to the "
                                         "100000000 bytes expected");
  }
}

}  // namespace
}  // namespace vrv

namespace vrv {
namespace {

// A zlib stream longer than the reader's 1 MiB chunk of compressed bytes (random samples do not
// compress) reads back sample for sample; cut short, it is refused naming how far it got.
TEST(MetaImageReader, InflatesAStreamLongerThanOneChunkSampleForSample) {
  const int nx = 128, ny = 128, nz = 100;
  std::vector<unsigned char> samples(static_cast<std::size_t>(nx) * ny * nz);
  std::uint32_t state = 12345;
  for (auto& s : samples) s = static_cast<unsigned char>((state = state * 1664525u + 1013904223u) >> 24);
  uLongf packed_size = compressBound(samples.size());
  std::string packed(packed_size, '\0');
  ASSERT_EQ(compress2(reinterpret_cast<Bytef*>(packed.data()), &packed_size, samples.data(), samples.size(), 1), Z_OK);
  packed.resize(packed_size);
  ASSERT_GT(packed.size(), std::size_t{1} << 20);
  const std::string head = "NDims = 3\nDimSize = 128 128 100\nElementType = MET_UCHAR\nCompressedData = True\n"
                           "ElementDataFile = volume.raw\n";
  {
    MetaImageTempFiles t(head, packed);
    const Volume v = read_metaimage(t.header);
    ASSERT_EQ(v.count(), samples.size());
    std::size_t differ = 0;
    for (std::size_t n = 0; n < samples.size(); ++n) differ += v.sample(n) != samples[n];
    EXPECT_EQ(differ, 0u);
  }
  MetaImageTempFiles cut(head, packed.substr(0, packed.size() - 1000));
  try {
    read_metaimage(cut.header);
    ADD_FAILURE() << "read";
  } catch (const VolumeFileError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(cut.header.string() + ": CompressedData: compressed data end after ", 0), 0u) << what;
    EXPECT_NE(what.find(" of 1638400 bytes"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace vrv
