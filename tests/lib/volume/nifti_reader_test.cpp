#include "lib/volume/nifti_reader.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "tests/lib/volume/volume_fixtures.h"

namespace vrv {
namespace {

Volume nifti_volume(const std::filesystem::path& p) { return read_nifti(p); }

// nibabel wrote them: eight types in both byte orders, a qform with qfac -1 and a rescale
// (.nii.gz), an sform that permutes and mirrors the axes.
TEST(NiftiReader, ReadsEveryFixtureAsNibabelWroteIt) { EXPECT_EQ(test::expect_fixtures("nifti_", nifti_volume), 16); }

TEST(NiftiReader, RefusesBadFilesInOneLine) { EXPECT_EQ(test::expect_bad_fixtures("bad_nifti_", nifti_volume), 3); }

const std::filesystem::path kNibabelData = "/usr/lib/python3/dist-packages/nibabel/tests/data";

// The NIfTI files Debian's python3-nibabel ships, against what nibabel reads in them
// (nibabel_expected.json, make_volume_fixtures.py): affine, type, shape, header scaling and
// every value (CRC-32 of the float64 values, their sum and every 97th).
TEST(NiftiReader, ReadsNibabelsTestDataAsNibabelDoes) {
  const auto& files = test::volume_expected("nibabel_expected.json")["files"];
  ASSERT_EQ(files.size(), 4u);
  for (const auto& c : files) {
    const std::string file = c["file"];
    SCOPED_TRACE(file);
    const Volume v = read_nifti(kNibabelData / file);
    test::expect_geometry(c, v);
    EXPECT_EQ(v.slope, c["slope"].get<double>());
    EXPECT_EQ(v.intercept, c["intercept"].get<double>());
    std::vector<double> values(v.count());
    double sum = 0;
    int nans = 0;
    for (std::size_t n = 0; n < values.size(); ++n) {
      values[n] = v.sample(n);
      if (std::isnan(values[n])) ++nans;
      else sum += values[n];
    }
    EXPECT_EQ(nans, c["nans"].get<int>());
    // The CRC is over the values' bytes as Python wrote them, little-endian (x86-64, arm64).
    const auto crc = crc32(0, reinterpret_cast<const Bytef*>(values.data()), static_cast<uInt>(values.size() * 8));
    EXPECT_EQ(crc, c["crc32"].get<unsigned long>());
    EXPECT_EQ(sum, c["sum"].get<double>());
    for (std::size_t i = 0; i < c["every97"].size(); ++i) {
      if (c["every97"][i].is_null()) EXPECT_TRUE(std::isnan(values[97 * i])) << 97 * i;
      else EXPECT_EQ(values[97 * i], c["every97"][i].get<double>()) << 97 * i;
    }
  }
}

// anatomical.nii has qfac = -1: a reader that ignores it mirrors the third axis (z step -2).
TEST(NiftiReader, HonoursQfac) {
  const Volume v = read_nifti(kNibabelData / "anatomical.nii");
  EXPECT_EQ(v.steps()(2, 2), 2.0);
  EXPECT_EQ(v.steps()(0, 0), -2.0);
}

// niftilib prints a bad datatype on stderr whatever its debug level: it is the reason in our one
// line, and nothing else is printed.
TEST(NiftiReader, NiftilibsOwnErrorIsTheReason) {
  std::vector<char> h(348 + 4 + 64 * 4, 0);
  const auto put = [&](std::size_t at, auto value) { std::memcpy(h.data() + at, &value, sizeof value); };
  put(0, std::int32_t{348});
  const std::int16_t dim[8] = {3, 4, 4, 4, 1, 1, 1, 1};
  std::memcpy(h.data() + 40, dim, sizeof dim);
  put(70, std::int16_t{9999});  // datatype: none
  put(72, std::int16_t{32});
  const float pixdim[8] = {1, 1, 1, 1, 1, 1, 1, 1};
  std::memcpy(h.data() + 76, pixdim, sizeof pixdim);
  put(108, 352.0f);
  std::memcpy(h.data() + 344, "n+1", 4);
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "vrv_nifti_bad_datatype.nii";
  std::ofstream(file, std::ios::binary).write(h.data(), static_cast<std::streamsize>(h.size()));
  testing::internal::CaptureStderr();
  std::string message;
  try {
    read_nifti(file);
  } catch (const std::exception& e) {
    message = e.what();
  }
  const std::string printed = testing::internal::GetCapturedStderr();
  std::filesystem::remove(file);
  EXPECT_NE(message.find("(header): not a readable NIfTI or ANALYZE header (niftilib: nifti_convert_n1hdr2nim: "
                         "bad datatype)"),
            std::string::npos)
      << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_EQ(printed, "");
}

TEST(NiftiReader, RefusesNibabelsTimeSeries) {
  for (const auto& b : test::volume_expected("nibabel_expected.json")["refused"])
    test::expect_refused(kNibabelData / b["file"].get<std::string>(), b, nifti_volume);
}

}  // namespace
}  // namespace vrv
