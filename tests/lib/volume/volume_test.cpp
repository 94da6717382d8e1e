#include "lib/volume/volume.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include <zlib.h>

#include "lib/volume/nrrd_reader.h"
#include "lib/volume/vti_reader.h"
#include "tests/lib/volume/volume_fixtures.h"

namespace vrv {
namespace {

// 5 x 4 x 3 float64 samples: 480 bytes; index axes along x, y, z, or i and j swapped.
Volume header_only(bool permuted) {
  Volume v;
  v.dims = {5, 4, 3};
  v.sign = {1, -1, 1};  // a mirrored axis is swapped end for end: no bits
  if (permuted) v.axis = {1, 0, 2};
  return v;
}

std::string refusal(const Volume& v, std::uint64_t reader_bytes, std::int64_t max_bytes, bool grid_copies) {
  try {
    check_budget("v.nrrd", "sizes", v, ScalarType::f64, reader_bytes, {max_bytes, kMaxVolumeSamples, grid_copies});
    return "";
  } catch (const VolumeFileError& e) {
    return e.what();
  }
}

// The peak is the samples plus the larger of the reader's buffer and the bits that put a
// permuted header's samples in world order (60 samples: 8 bytes).
TEST(VolumeBudget, ThePeakIsTheSamplesAndTheLargerOfTheReadersBufferAndTheGridsCopy) {
  EXPECT_EQ(refusal(header_only(false), 0, 480, true), "");  // mirrored, not permuted
  EXPECT_EQ(refusal(header_only(false), 0, 479, true),
            "v.nrrd: sizes: 5 x 4 x 3 float64 samples take 480 bytes, more than the 479 allowed (--max-memory)");
  EXPECT_EQ(refusal(header_only(false), 100, 580, true), "");
  EXPECT_EQ(refusal(header_only(false), 100, 579, true),
            "v.nrrd: sizes: 5 x 4 x 3 float64 samples take 480 bytes, 580 at the peak, more than the 579 "
            "allowed (--max-memory)");
  EXPECT_EQ(refusal(header_only(true), 0, 487, true),
            "v.nrrd: sizes: 5 x 4 x 3 float64 samples take 480 bytes, 488 at the peak, more than the 487 "
            "allowed (--max-memory)");
  EXPECT_EQ(refusal(header_only(true), 0, 488, true), "");
  EXPECT_EQ(refusal(header_only(true), 0, 480, false), "");  // no reordering asked for
  EXPECT_EQ(refusal(header_only(true), 100, 580, true), "");
}

// A reader that reads straight into the samples is held to one copy: a raw NRRD of exactly the
// budget is read (it was refused when every reader counted two copies); what Teem reads into a
// buffer of its own (ascii) counts that buffer.
TEST(VolumeBudget, AReaderIsChargedForWhatItHolds) {
  const auto raw = test::volume_fixture_dir() / "nrrd_f64_little.nrrd";
  EXPECT_EQ(read_nrrd(raw, {480}).count(), 60u);
  EXPECT_THROW(read_nrrd(raw, {479}), VolumeFileError);
  const auto ascii = std::filesystem::temp_directory_path() / "vrv_budget_ascii.nrrd";
  std::ofstream(ascii) << "NRRD0004\ntype: uint16\ndimension: 3\nsizes: 2 2 2\nencoding: ascii\n\n1 2 3 4 5 6 7 8\n";
  EXPECT_EQ(read_nrrd(ascii, {32}).count(), 8u);
  try {
    read_nrrd(ascii, {31});
    ADD_FAILURE() << "read";
  } catch (const VolumeFileError& e) {
    EXPECT_EQ(std::string(e.what()), ascii.string() + ": sizes: 2 x 2 x 2 uint16 samples take 16 bytes, 32 at the "
                                                      "peak, more than the 31 allowed (--max-memory)");
  }
  std::filesystem::remove(ascii);
}

// A VTI file's XML text is held while its inline arrays are read: text longer than the budget is
// refused as it is read, while appended raw data (read from the file) fit the same budget.
TEST(VolumeBudget, AVtiFilesInlineTextCountsAndItsAppendedDataDoNot) {
  std::string values, raw;
  for (int n = 0; n < 1000; ++n) values += std::to_string(n % 200) + " ", raw += static_cast<char>(n % 200);
  const std::string head = "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
                           " <ImageData WholeExtent=\"0 9 0 9 0 9\">\n  <Piece>\n   <PointData>\n";
  const std::string tail = "   </PointData>\n  </Piece>\n </ImageData>\n";
  const auto inline_path = std::filesystem::temp_directory_path() / "vrv_budget_inline.vti";
  const auto appended_path = std::filesystem::temp_directory_path() / "vrv_budget_appended.vti";
  std::ofstream(inline_path) << head << "    <DataArray type=\"UInt8\" format=\"ascii\">" << values << "</DataArray>\n"
                             << tail << "</VTKFile>\n";
  std::string size(4, '\0');
  size[0] = static_cast<char>(1000 & 0xff), size[1] = static_cast<char>(1000 >> 8);
  std::ofstream(appended_path, std::ios::binary) << head << "    <DataArray type=\"UInt8\" format=\"appended\" offset=\"0\"/>\n"
                                                 << tail << " <AppendedData encoding=\"raw\">_" << size << raw
                                                 << "</AppendedData>\n</VTKFile>\n";
  try {
    read_vti(inline_path, {1500});
    ADD_FAILURE() << "read";
  } catch (const VolumeFileError& e) {
    EXPECT_EQ(std::string(e.what()), inline_path.string() + ": (file): its XML text, held while its arrays are "
                                                            "read, is longer than the 1500 bytes allowed (--max-memory)");
  }
  EXPECT_EQ(read_vti(appended_path, {1500}).count(), 1000u);
  EXPECT_EQ(read_vti(inline_path, {5000}).count(), 1000u);
  std::filesystem::remove(inline_path);
  std::filesystem::remove(appended_path);
}

// VTK's zlib blocks of one byte each (1000 blocks, each its own stream): the blocks' size table
// (8 bytes a block) is held while they are inflated and counted against the budget; read within
// a budget that holds it, block by block from one open file.
TEST(VolumeBudget, AVtiFilesBlockSizeTableCounts) {
  std::string samples, blocks, sizes;
  for (int n = 0; n < 1000; ++n) {
    samples += static_cast<char>(n * 7 % 256);
    uLongf size = compressBound(1);
    std::string block(size, '\0');
    compress2(reinterpret_cast<Bytef*>(block.data()), &size, reinterpret_cast<const Bytef*>(samples.data() + n), 1, 6);
    block.resize(size);
    blocks += block;
    for (int b = 0; b < 8; ++b) sizes += static_cast<char>(size >> (8 * b) & 0xff);
  }
  std::string header;
  for (std::uint64_t v : {std::uint64_t{1000}, std::uint64_t{1}, std::uint64_t{1}})
    for (int b = 0; b < 8; ++b) header += static_cast<char>(v >> (8 * b) & 0xff);
  const auto path = std::filesystem::temp_directory_path() / "vrv_blocks.vti";
  std::ofstream(path, std::ios::binary)
      << "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\" "
         "header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\">\n <ImageData WholeExtent=\"0 9 0 9 0 9\">\n  <Piece>\n"
         "   <PointData>\n    <DataArray type=\"UInt8\" format=\"appended\" offset=\"0\"/>\n   </PointData>\n  </Piece>\n"
         " </ImageData>\n <AppendedData encoding=\"raw\">_"
      << header << sizes << blocks << "</AppendedData>\n</VTKFile>\n";
  try {
    read_vti(path, {4000});
    ADD_FAILURE() << "read";
  } catch (const VolumeFileError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(path.string() + ": DataArray: 1000 compressed blocks of 1 bytes: their 8000-byte size table is "
                                         "more than the ", 0), 0u) << what;
  }
  const Volume v = read_vti(path, {20000});
  ASSERT_EQ(v.count(), 1000u);
  for (int n = 0; n < 1000; ++n) ASSERT_EQ(v.sample(static_cast<std::size_t>(n)), n * 7 % 256) << n;
  std::filesystem::remove(path);
}

// Written here, apart from the reader's libb64, so the decoder is not checked against itself.
std::string base64(const std::string& bytes) {
  static const char* abc = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    std::uint32_t n = static_cast<unsigned char>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) n |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    if (i + 2 < bytes.size()) n |= static_cast<unsigned char>(bytes[i + 2]);
    out += abc[n >> 18 & 63];
    out += abc[n >> 12 & 63];
    out += i + 1 < bytes.size() ? abc[n >> 6 & 63] : '=';
    out += i + 2 < bytes.size() ? abc[n & 63] : '=';
    if (i % 57 == 54) out += "\n  ";  // VTK's writers break lines; whitespace is ignored
  }
  return out;
}

std::string le32(std::size_t n) {
  std::string out(4, '\0');
  for (int b = 0; b < 4; ++b) out[b] = static_cast<char>(n >> (8 * b) & 0xff);
  return out;
}

// VTK's zlib layout, encoded as VTK encodes it: the header (blocks, block size, last block's
// size, each compressed size) apart from the blocks, so '=' padding may sit mid-stream.
std::string vtk_zlib_base64(const std::string& data) {
  constexpr std::size_t kBlock = 32768;
  std::string head, body;
  std::size_t blocks = 0;
  for (std::size_t at = 0; at < data.size(); at += kBlock, ++blocks) {
    const std::size_t n = std::min(kBlock, data.size() - at);
    uLongf size = compressBound(n);
    std::string block(size, '\0');
    compress2(reinterpret_cast<Bytef*>(block.data()), &size, reinterpret_cast<const Bytef*>(data.data() + at), n, 6);
    block.resize(size);
    head += le32(size);
    body += block;
  }
  const std::size_t last = data.size() - (blocks - 1) * kBlock;
  return base64(le32(blocks) + le32(kBlock) + le32(last) + head) + base64(body);
}

// 128 x 128 x 200 uint8 samples (pseudo-random: they do not compress), whose base64 text (4.4 M
// characters) is longer than the chunks the reader decodes at a time (4 Mi characters in place,
// 1 MiB of appended text): inline, appended, and appended in zlib blocks after another array (its
// offset counts base64 characters, as VTK writes and seeks it).
TEST(VtiBase64, InlineAndAppendedArraysDecodeAcrossChunks) {
  const int nx = 128, ny = 128, nz = 200;
  std::string samples(static_cast<std::size_t>(nx) * ny * nz, '\0');
  std::uint32_t state = 12345;
  for (char& c : samples) c = static_cast<char>((state = state * 1664525u + 1013904223u) >> 24);
  const std::string stream = base64(le32(samples.size()) + samples);
  const std::string other = vtk_zlib_base64("0123456789"), zlib_stream = vtk_zlib_base64(samples);
  auto image = [](const std::string& compressor, const std::string& arrays) {
    return "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\"" + compressor +
           ">\n <ImageData WholeExtent=\"0 127 0 127 0 199\">\n  <Piece>\n   <PointData Scalars=\"v\">\n" + arrays +
           "   </PointData>\n  </Piece>\n </ImageData>\n";
  };
  const std::string appended = "    <DataArray type=\"UInt8\" Name=\"v\" format=\"appended\" offset=\"0\"/>\n";
  const std::string files[] = {
      image("", "    <DataArray type=\"UInt8\" Name=\"v\" format=\"binary\">\n" + stream + "\n    </DataArray>\n") +
          "</VTKFile>\n",
      image("", appended) + " <AppendedData encoding=\"base64\">\n  _" + stream + "\n </AppendedData>\n</VTKFile>\n",
      image(" compressor=\"vtkZLibDataCompressor\"",
            "    <DataArray type=\"UInt8\" Name=\"w\" format=\"appended\" offset=\"0\"/>\n"
            "    <DataArray type=\"UInt8\" Name=\"v\" format=\"appended\" offset=\"" + std::to_string(other.size()) + "\"/>\n") +
          " <AppendedData encoding=\"base64\">\n  _" + other + zlib_stream + "\n </AppendedData>\n</VTKFile>\n"};
  const auto path = std::filesystem::temp_directory_path() / "vrv_base64.vti";
  for (const std::string& text : files) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
    const Volume v = read_vti(path);
    ASSERT_EQ(v.dims, (std::array<int, 3>{nx, ny, nz}));
    const auto& got = std::get<std::vector<std::uint8_t>>(v.samples);
    ASSERT_EQ(got.size(), samples.size());
    std::size_t wrong = 0;
    for (std::size_t n = 0; n < got.size(); ++n) wrong += got[n] != static_cast<unsigned char>(samples[n]);
    EXPECT_EQ(wrong, 0u) << text.substr(0, 400);
  }
  // Appended base64 text cut short: one line naming the file.  Its decoded size is bounded from
  // the text's length (the array's header is refused against the bound), or, when white space
  // pads the text, found short as it is decoded.
  const std::string& whole = files[1];
  const std::string half = whole.substr(0, whole.size() / 2);
  for (const std::string& padding : {std::string(), std::string(3000000, ' ')}) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << half << padding << "\n </AppendedData>\n</VTKFile>\n";
    try {
      read_vti(path);
      ADD_FAILURE() << "read";
    } catch (const VolumeFileError& e) {
      EXPECT_EQ(std::string(e.what()),
                path.string() + (padding.empty() ? ": DataArray: truncated: 1702971 bytes, the array's header needs 3276804"
                                                 : ": AppendedData: truncated: the base64 data end before byte 3276804 of the array"));
    }
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace vrv
