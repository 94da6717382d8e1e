#include "lib/volume/volume.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <memory>
#include <span>

#include <fmt/format.h>
#include <zlib.h>

#include "lib/io/error_line.h"

namespace vrv {

void volume_fail(const std::filesystem::path& file, std::string_view what, std::string_view reason) {
  throw VolumeFileError(error_line(file.string(), what, reason));
}

std::vector<double> header_numbers(const std::filesystem::path& file, std::string_view what, std::string_view text,
                                   std::size_t count) {
  std::vector<double> out;
  const char* p = text.data();
  const char* end = p + text.size();
  while (p < end) {
    while (p < end && std::isspace(static_cast<unsigned char>(*p))) ++p;
    if (p == end) break;
    double x = 0;
    const auto [next, ec] = std::from_chars(p, end, x);
    if (ec != std::errc() || !std::isfinite(x))
      volume_fail(file, what, fmt::format("\"{}\" is not a list of finite numbers", text.substr(0, 80)));
    out.push_back(x);
    p = next;
  }
  if (out.size() != count) volume_fail(file, what, fmt::format("{} numbers, expected {}", out.size(), count));
  return out;
}

std::string_view to_string(ScalarType t) {
  constexpr std::string_view names[] = {"uint8", "int8", "uint16", "int16",
                                        "uint32", "int32", "float32", "float64"};
  return names[static_cast<int>(t)];
}

std::size_t scalar_bytes(ScalarType t) {
  constexpr std::size_t bytes[] = {1, 1, 2, 2, 4, 4, 4, 8};
  return bytes[static_cast<int>(t)];
}

Eigen::Matrix3d Volume::steps() const {
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  for (int a = 0; a < 3; ++a) m(axis[a], a) = sign[a] * spacing[a];
  return m;
}

std::array<int, 3> checked_dims(const std::filesystem::path& file, std::string_view what,
                                const std::array<std::int64_t, 3>& dims) {
  std::array<int, 3> out{};
  std::int64_t total = 1;
  for (int a = 0; a < 3; ++a) {
    if (dims[a] < 1 || dims[a] > kMaxVolumeSamples)
      volume_fail(file, what, fmt::format("size {} on axis {} (expected 1 to {})", dims[a], a, kMaxVolumeSamples));
    total *= dims[a];
    if (total > kMaxVolumeSamples)
      volume_fail(file, what, fmt::format("{} x {} x {} samples: more than {}", dims[0], dims[1], dims[2],
                                          kMaxVolumeSamples));
    out[a] = static_cast<int>(dims[a]);
  }
  return out;
}

void check_budget(const std::filesystem::path& file, std::string_view what, const Volume& v, ScalarType t,
                  std::uint64_t reader_bytes, const VolumeReadOptions& options) {
  const std::array<int, 3>& d = v.dims;
  const std::int64_t samples = std::int64_t{d[0]} * d[1] * d[2];
  if (samples > options.max_samples)
    volume_fail(file, what, fmt::format("{} x {} x {} samples: more than {}", d[0], d[1], d[2], options.max_samples));
  const std::uint64_t bytes = static_cast<std::uint64_t>(samples) * scalar_bytes(t);
  const std::uint64_t reorder = options.reorders_to_world_order && !v.axes_along_world() ? (samples + 7) / 8 : 0;
  const std::uint64_t peak = bytes + std::max(reader_bytes, reorder);
  if (peak > static_cast<std::uint64_t>(std::max<std::int64_t>(options.max_bytes, 0)))
    volume_fail(file, what, fmt::format("{} x {} x {} {} samples take {} bytes{}, more than the {} allowed (--max-memory)",
                                        d[0], d[1], d[2], to_string(t), bytes,
                                        peak > bytes ? fmt::format(", {} at the peak", peak) : "",
                                        options.max_bytes));
}

void set_axis_aligned(Volume& v, const Eigen::Matrix3d& steps, const std::filesystem::path& file,
                      std::string_view what) {
  constexpr double kOffAxis = 1e-6;
  bool used[3] = {false, false, false};
  for (int a = 0; a < 3; ++a) {
    const Eigen::Vector3d c = steps.col(a);
    if (!c.allFinite()) volume_fail(file, what, fmt::format("index axis {} has a non-finite direction", a));
    const double length = c.norm();
    if (!(length > 0) || !std::isfinite(length))
      volume_fail(file, what, fmt::format("index axis {} has a zero or overflowing step", a));
    int w = 0;
    c.cwiseAbs().maxCoeff(&w);
    for (int b = 0; b < 3; ++b)
      if (b != w && std::abs(c[b]) > kOffAxis * length)
        volume_fail(file, what,
                    fmt::format("oblique direction [{}, {}, {}] of index axis {} not supported "
                                "(only axis-aligned volumes)", c[0], c[1], c[2], a));
    if (used[w]) volume_fail(file, what, fmt::format("index axes share world axis {}", w));
    used[w] = true;
    v.axis[a] = w;
    v.sign[a] = c[w] < 0 ? -1 : 1;
    v.spacing[a] = std::abs(c[w]);  // the header's own number (not the norm) when axis-aligned
  }
}

namespace {

// Samples stored in the file's byte order, put in this machine's (in place).
template <class T>
void to_native_order(std::vector<T>& v, bool big_endian) {
  if (sizeof(T) > 1 && big_endian != (std::endian::native == std::endian::big)) {
    auto* raw = reinterpret_cast<unsigned char*>(v.data());
    for (std::size_t n = 0; n < v.size(); ++n) std::reverse(raw + n * sizeof(T), raw + (n + 1) * sizeof(T));
  }
}

template <class T>
std::vector<T> decode(const unsigned char* bytes, std::size_t count, bool big_endian) {
  std::vector<T> out(count);
  if (count > 0) std::memcpy(out.data(), bytes, count * sizeof(T));
  to_native_order(out, big_endian);
  return out;
}

}  // namespace

VolumeSamples samples_from_bytes(ScalarType t, const unsigned char* bytes, std::size_t count,
                                 bool big_endian) {
  switch (t) {
    case ScalarType::u8: return decode<std::uint8_t>(bytes, count, big_endian);
    case ScalarType::i8: return decode<std::int8_t>(bytes, count, big_endian);
    case ScalarType::u16: return decode<std::uint16_t>(bytes, count, big_endian);
    case ScalarType::i16: return decode<std::int16_t>(bytes, count, big_endian);
    case ScalarType::u32: return decode<std::uint32_t>(bytes, count, big_endian);
    case ScalarType::i32: return decode<std::int32_t>(bytes, count, big_endian);
    case ScalarType::f32: return decode<float>(bytes, count, big_endian);
    case ScalarType::f64: return decode<double>(bytes, count, big_endian);
  }
  return {};
}

void check_inflatable(std::uint64_t size, std::size_t expected, const std::filesystem::path& file,
                      std::string_view what) {
  // No deflate stream inflates more than 1032-fold (258 bytes from one 2-bit code at best); 64
  // bytes for a gzip header and trailer.
  if (expected / 1032 > size + 64)
    volume_fail(file, what, fmt::format("{} bytes of compressed data cannot inflate to the {} bytes expected",
                                        size, expected));
}

void inflate_chunks_into(std::size_t size, const CompressedChunks& next, unsigned char* out, std::size_t expected,
                         const std::filesystem::path& file, std::string_view what) {
  check_inflatable(size, expected, file, what);
  z_stream z{};
  // 15 + 32: zlib or gzip header, detected (MetaImage and VTK write zlib, NRRD gzip).
  if (inflateInit2(&z, 15 + 32) != Z_OK) volume_fail(file, what, "zlib initialisation failed");
  // Ended on every path: next() may throw (a read error) with the stream open.
  const std::unique_ptr<z_stream, int (*)(z_stream*)> end_stream(&z, inflateEnd);
  unsigned char beyond = 0;  // one byte past `expected`: output there means the stream is too long
  std::size_t done = 0;
  bool input_left = true;
  int rc = Z_OK;
  while (rc == Z_OK && done <= expected) {
    if (z.avail_in == 0 && input_left) {
      const std::span<const unsigned char> chunk = next();
      input_left = !chunk.empty();
      z.next_in = const_cast<unsigned char*>(chunk.data());
      z.avail_in = static_cast<uInt>(chunk.size());  // chunks of at most 1 GiB
    }
    const bool past = done == expected;
    const uInt out_chunk = past ? 1 : static_cast<uInt>(std::min<std::size_t>(expected - done, 1u << 30));
    z.next_out = past ? &beyond : out + done;
    z.avail_out = out_chunk;
    rc = inflate(&z, Z_NO_FLUSH);
    done += out_chunk - z.avail_out;
    if (rc == Z_BUF_ERROR && !input_left) break;  // input ended early
    if (rc == Z_BUF_ERROR) rc = Z_OK;
  }
  if (rc != Z_STREAM_END && rc != Z_OK && rc != Z_BUF_ERROR)
    volume_fail(file, what, fmt::format("damaged compressed data ({})", z.msg ? z.msg : "zlib error"));
  if (done > expected)
    volume_fail(file, what, fmt::format("compressed data inflate to more than the {} bytes expected", expected));
  if (rc != Z_STREAM_END || done != expected)
    volume_fail(file, what, fmt::format("compressed data end after {} of {} bytes", done, expected));
}

void inflate_into(const unsigned char* data, std::size_t size, unsigned char* out, std::size_t expected,
                  const std::filesystem::path& file, std::string_view what) {
  std::size_t given = 0;
  const auto next = [&] {
    const std::size_t n = std::min<std::size_t>(size - given, std::size_t{1} << 30);
    given += n;
    return std::span<const unsigned char>(data + given - n, n);
  };
  inflate_chunks_into(size, next, out, expected, file, what);
}

namespace {

std::ifstream open_file(const std::filesystem::path& file) {
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) volume_fail(file, "(file)", "is a directory");
  std::ifstream in(file, std::ios::binary);
  if (!in) volume_fail(file, "(file)", fmt::format("cannot open: {}", std::strerror(errno)));
  return in;
}

}  // namespace

std::string read_file_head(const std::filesystem::path& file, std::size_t bytes) {
  std::ifstream in = open_file(file);
  std::string head;
  char buffer[1 << 16];
  while (head.size() < bytes && (in.read(buffer, sizeof buffer) || in.gcount() > 0))
    head.append(buffer, static_cast<std::size_t>(in.gcount()));
  if (in.bad()) volume_fail(file, "(file)", "read error");
  if (head.size() > bytes) head.resize(bytes);
  return head;
}

std::uint64_t file_size_of(const std::filesystem::path& file) {
  std::ifstream in = open_file(file);
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (!in || size < 0) volume_fail(file, "(file)", "cannot find its size");
  return static_cast<std::uint64_t>(size);
}

void inflate_file_range_into(const std::filesystem::path& file, std::uint64_t offset, std::uint64_t size,
                             unsigned char* out, std::size_t expected, const std::filesystem::path& named,
                             std::string_view what) {
  std::ifstream in = open_file(file);
  in.seekg(static_cast<std::streamoff>(offset));
  std::vector<unsigned char> buffer(static_cast<std::size_t>(std::min<std::uint64_t>(size, std::uint64_t{1} << 20)));
  std::uint64_t left = size;
  const auto next = [&] {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(left, buffer.size()));
    in.read(reinterpret_cast<char*>(buffer.data()), static_cast<std::streamsize>(n));
    if (static_cast<std::size_t>(in.gcount()) != n)
      volume_fail(file, "(data)", fmt::format("cannot read {} bytes from offset {} (truncated or damaged)", size, offset));
    left -= n;
    return std::span<const unsigned char>(buffer.data(), n);
  };
  inflate_chunks_into(static_cast<std::size_t>(size), next, out, expected, named, what);
}

void read_file_range(const std::filesystem::path& file, std::uint64_t offset, unsigned char* out,
                     std::size_t bytes) {
  std::ifstream in = open_file(file);
  in.seekg(static_cast<std::streamoff>(offset));
  in.read(reinterpret_cast<char*>(out), static_cast<std::streamsize>(bytes));
  if (!in || static_cast<std::size_t>(in.gcount()) != bytes)
    volume_fail(file, "(data)", fmt::format("cannot read {} bytes from offset {} (truncated or damaged)", bytes, offset));
}

}  // namespace vrv

namespace vrv {

VolumeSamples read_stored_samples(const StoredSamples& d, ScalarType t, std::size_t count, bool big_endian,
                                  const std::filesystem::path& file, std::string_view what) {
  const std::size_t need = count * scalar_bytes(t);
  if (!d.compressed) {
    if (d.available < need)
      volume_fail(file, what, fmt::format("truncated: {} bytes of data where {} {} samples need {}", d.available, count,
                                          to_string(t), need));
    return read_samples(t, count, big_endian,
                        [&](unsigned char* out, std::size_t bytes) { read_file_range(d.path, d.offset, out, bytes); });
  }
  check_inflatable(d.available, need, file, what);
  return read_samples(t, count, big_endian, [&](unsigned char* out, std::size_t bytes) {
    inflate_file_range_into(d.path, d.offset, d.available, out, bytes, file, what);
  });
}

VolumeSamples read_samples(ScalarType t, std::size_t count, bool big_endian,
                           const std::function<void(unsigned char*, std::size_t)>& read) {
  VolumeSamples samples = samples_from_bytes(t, nullptr, 0, big_endian);  // the alternative for t
  std::visit(
      [&](auto& v) {
        v.resize(count);
        read(reinterpret_cast<unsigned char*>(v.data()), count * sizeof(v[0]));
        to_native_order(v, big_endian);
      },
      samples);
  return samples;
}

}  // namespace vrv
