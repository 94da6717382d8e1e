#pragma once
// A volume read from a user's file (NRRD, NIfTI, MetaImage, VTI): samples in their own scalar
// type, index order (i fastest), and an axis-aligned placement in the file's world frame.
//
// World position of sample (i, j, k): origin + sum over index axes a of
//   sign[a] * spacing[a] * index[a] along world axis axis[a]
// (axis is a permutation of 0, 1, 2).  Oblique directions, several components per sample and
// time series are refused by the readers (VolumeFileError).
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <Eigen/Dense>

#include "analytic/vec3.h"

namespace vrv {

// One line: "<file>: <what>: <reason>" (lib/io/error_line), e.g.
// "head.nii.gz: dim: 4-D (time series of 20 frames) not supported".
class VolumeFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};
[[noreturn]] void volume_fail(const std::filesystem::path& file, std::string_view what,
                              std::string_view reason);

// A header value that is a list of exactly `count` finite numbers separated by white space (the
// MetaImage and VTI headers' spacing, origin, sizes); volume_fail naming `what` otherwise.
std::vector<double> header_numbers(const std::filesystem::path& file, std::string_view what, std::string_view text,
                                   std::size_t count);

enum class ScalarType { u8, i8, u16, i16, u32, i32, f32, f64 };
std::string_view to_string(ScalarType t);
std::size_t scalar_bytes(ScalarType t);

// The variant's alternatives are in ScalarType's order (index() == the enum's value).
using VolumeSamples = std::variant<std::vector<std::uint8_t>, std::vector<std::int8_t>,
                                   std::vector<std::uint16_t>, std::vector<std::int16_t>,
                                   std::vector<std::uint32_t>, std::vector<std::int32_t>,
                                   std::vector<float>, std::vector<double>>;

// Largest volume a reader accepts, checked from the header before any data is read (2^31
// samples: an 8 GiB float volume); the scene's own, smaller cap is the grid's (scene_file).
inline constexpr std::int64_t kMaxVolumeSamples = std::int64_t{1} << 31;

struct Volume {
  std::array<int, 3> dims{1, 1, 1};
  Vec3 spacing{1, 1, 1};  // positive, world length per index step
  Vec3 origin{0, 0, 0};   // world position of sample (0, 0, 0)
  std::array<int, 3> axis{0, 1, 2};
  std::array<int, 3> sign{1, 1, 1};
  VolumeSamples samples;
  // value = slope * stored + intercept where the header states it (NIfTI scl_slope/scl_inter).
  bool has_rescale = false;
  double slope = 1, intercept = 0;
  // Every file the samples came from (a detached header's data file too): what the scene hash
  // covers.
  std::vector<std::filesystem::path> files;

  ScalarType type() const { return static_cast<ScalarType>(samples.index()); }
  std::size_t count() const {
    return std::visit([](const auto& v) { return v.size(); }, samples);
  }
  double sample(std::size_t n) const {
    return std::visit([n](const auto& v) { return static_cast<double>(v[n]); }, samples);
  }
  double sample(int i, int j, int k) const {
    return sample((static_cast<std::size_t>(k) * dims[1] + j) * dims[0] + i);
  }
  // The 3x3 matrix whose column a is index axis a's step in world coordinates.
  Eigen::Matrix3d steps() const;
  // Index axis a along world axis a (mirrored or not).
  bool axes_along_world() const { return axis == std::array<int, 3>{0, 1, 2}; }
};

// What a reader may allocate for the samples, checked from the header before any data is read
// (`vrv --max-memory`, the fuzz harnesses' small budget).
struct VolumeReadOptions {
  std::int64_t max_bytes = std::int64_t{16} << 30;
  std::int64_t max_samples = kMaxVolumeSamples;
  // The caller puts the samples in world order where they are (a scene placing the volume by its
  // header, lib/volume/volume_grid), with one bit a sample beside them when the header's index
  // axes are permuted: in the budget.
  bool reorders_to_world_order = false;
};
// Refuses more than options.max_samples samples, or a peak above options.max_bytes, naming
// `what`: the samples, plus the larger of what the reader holds beside them while reading
// (`reader_bytes`: Teem's buffer, a file's text) and the caller's bits while reordering them.
// `v` has its dims and axes (the header's geometry) set.
void check_budget(const std::filesystem::path& file, std::string_view what, const Volume& v, ScalarType t,
                  std::uint64_t reader_bytes, const VolumeReadOptions& options);

// Dims from a header: each in [1, 2^31) and their product at most kMaxVolumeSamples.
std::array<int, 3> checked_dims(const std::filesystem::path& file, std::string_view what,
                                const std::array<std::int64_t, 3>& dims);

// Spacing, axis and sign of `v` from index-axis steps (columns of `steps`, world units): each
// column must lie along one world axis (off-axis parts below 1e-6 of its length are rounding of
// the header's own arithmetic, e.g. NIfTI's quaternion) and the columns along different axes.
// Refuses oblique, zero or non-finite steps naming `what`.
void set_axis_aligned(Volume& v, const Eigen::Matrix3d& steps, const std::filesystem::path& file,
                      std::string_view what);

// `count` samples of type t from raw bytes in the given byte order.
VolumeSamples samples_from_bytes(ScalarType t, const unsigned char* bytes, std::size_t count,
                                 bool big_endian);

// `count` samples of type t read straight into their own storage by read(bytes, size), which
// throws when it cannot (no second copy of a scan while it is read), then put in this machine's
// byte order.
VolumeSamples read_samples(ScalarType t, std::size_t count, bool big_endian,
                           const std::function<void(unsigned char*, std::size_t)>& read);

// Where a file keeps its samples: `available` bytes from `offset` of `path`, raw or one zlib or
// gzip stream.
struct StoredSamples {
  std::filesystem::path path;
  std::uint64_t offset = 0;
  std::uint64_t available = 0;
  bool compressed = false;
};
// `count` samples of type t read from `d` straight into their own storage: raw from the file, or
// inflated from it a megabyte of compressed bytes at a time.  Too few bytes, or a stream that
// cannot hold the samples, are refused naming `file` and `what`.
VolumeSamples read_stored_samples(const StoredSamples& d, ScalarType t, std::size_t count, bool big_endian,
                                  const std::filesystem::path& file, std::string_view what);

// Refuses, naming `file` and `what`, `expected` bytes from a deflate stream of `size` bytes when
// no stream that short inflates that far: before anything is allocated for them.
void check_inflatable(std::uint64_t size, std::size_t expected, const std::filesystem::path& file,
                      std::string_view what);
// The next chunk of a compressed stream (at most 1 GiB; empty when the stream's bytes are all given).
using CompressedChunks = std::function<std::span<const unsigned char>()>;
// A zlib or gzip stream (auto-detected) of `size` bytes, given in chunks, inflated to exactly
// `expected` bytes at `out`; fewer, more, a damaged stream, or more than any deflate stream of
// `size` bytes can hold, are refused naming `file` and `what`.
void inflate_chunks_into(std::size_t size, const CompressedChunks& next, unsigned char* out, std::size_t expected,
                         const std::filesystem::path& file, std::string_view what);
// The same from `size` bytes in memory.
void inflate_into(const unsigned char* data, std::size_t size, unsigned char* out, std::size_t expected,
                  const std::filesystem::path& file, std::string_view what);

// The file's first `bytes` bytes (all of it when shorter).
std::string read_file_head(const std::filesystem::path& file, std::size_t bytes);
// The file's size; a directory or a file that cannot be opened is refused naming it.
std::uint64_t file_size_of(const std::filesystem::path& file);
// inflate_chunks_into from `size` bytes of `file` at `offset`, read 1 MiB at a time (no copy of
// the compressed data held); a read error names `file`, a bad stream `named` and `what`.
void inflate_file_range_into(const std::filesystem::path& file, std::uint64_t offset, std::uint64_t size,
                             unsigned char* out, std::size_t expected, const std::filesystem::path& named,
                             std::string_view what);
// Exactly `bytes` bytes from `offset` into out (no copy of the file held), or refused naming it.
void read_file_range(const std::filesystem::path& file, std::uint64_t offset, unsigned char* out,
                     std::size_t bytes);

}  // namespace vrv
