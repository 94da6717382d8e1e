#include "lib/io/npy.h"

#include <bit>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "lib/io/error_line.h"

namespace vrv {
namespace {

static_assert(std::endian::native == std::endian::little, "npy writer assumes a little-endian host");

constexpr std::string_view kMagic = "\x93NUMPY";

std::string shape_tuple(const std::vector<std::size_t>& shape) {
  std::string s = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) s += fmt::format("{}{}", i ? ", " : "", shape[i]);
  if (shape.size() == 1) s += ",";
  return s + ")";
}

template <class T>
std::string bytes_of(std::span<const T> values, const std::vector<std::size_t>& shape,
                     std::string_view dtype) {
  std::size_t n = 1;
  for (std::size_t s : shape) n *= s;
  if (n != values.size())
    throw std::invalid_argument(fmt::format("npy: shape {} holds {} values, got {}",
                                            shape_tuple(shape), n, values.size()));
  std::string header = fmt::format("{{'descr': '{}', 'fortran_order': False, 'shape': {}, }}",
                                   dtype, shape_tuple(shape));
  // Preamble (10 bytes) + header + '\n' is a multiple of 64, so the data are aligned.
  const std::size_t total = (10 + header.size() + 1 + 63) / 64 * 64;
  header.append(total - 10 - header.size() - 1, ' ');
  header += '\n';
  std::string out(kMagic);
  out += '\x01';
  out += '\x00';
  const auto len = static_cast<std::uint16_t>(header.size());
  out += static_cast<char>(len & 0xff);
  out += static_cast<char>(len >> 8);
  out += header;
  const std::size_t at = out.size();
  out.resize(at + values.size() * sizeof(T));
  if (!values.empty()) std::memcpy(out.data() + at, values.data(), values.size() * sizeof(T));
  return out;
}

[[noreturn]] void bad(const std::string& name, const std::string& reason) {
  // The reason may quote the file's header: one bounded line whatever it holds (error_line.h).
  throw std::runtime_error(error_line(name, "not a float .npy this reader takes", reason));
}

}  // namespace

std::string npy_bytes(std::span<const double> values, const std::vector<std::size_t>& shape) {
  return bytes_of(values, shape, "<f8");
}

std::string npy_bytes(std::span<const float> values, const std::vector<std::size_t>& shape) {
  return bytes_of(values, shape, "<f4");
}

NpyArray parse_npy(std::string_view bytes, const std::string& name) {
  if (bytes.size() < 10 || bytes.substr(0, 6) != kMagic) bad(name, "no \\x93NUMPY magic");
  const int major = static_cast<unsigned char>(bytes[6]);
  std::size_t header_len = 0, start = 0;
  if (major == 1) {
    header_len = static_cast<unsigned char>(bytes[8]) | static_cast<std::size_t>(static_cast<unsigned char>(bytes[9])) << 8;
    start = 10;
  } else if (major == 2 && bytes.size() >= 12) {
    for (int i = 0; i < 4; ++i)
      header_len |= static_cast<std::size_t>(static_cast<unsigned char>(bytes[8 + i])) << (8 * i);
    start = 12;
  } else {
    bad(name, fmt::format("format version {}", major));
  }
  if (bytes.size() < start + header_len) bad(name, "truncated header");
  const std::string header(bytes.substr(start, header_len));
  std::smatch m;
  NpyArray a;
  if (!std::regex_search(header, m, std::regex(R"('descr'\s*:\s*'([^']*)')"))) bad(name, "no descr");
  a.dtype = m[1];
  if (a.dtype != "<f8" && a.dtype != "<f4") bad(name, "dtype " + a.dtype);
  if (!std::regex_search(header, m, std::regex(R"('fortran_order'\s*:\s*(True|False))")) || m[1] == "True")
    bad(name, "not C order");
  if (!std::regex_search(header, m, std::regex(R"('shape'\s*:\s*\(([^)]*)\))"))) bad(name, "no shape");
  std::size_t n = 1;
  std::stringstream dims(m[1].str());
  for (std::string item; std::getline(dims, item, ',');) {
    const std::size_t first = item.find_first_not_of(' ');
    if (first == std::string::npos) continue;
    std::size_t d = 0;
    const auto [end, ec] = std::from_chars(item.data() + first, item.data() + item.size(), d);
    if (ec != std::errc() || item.find_first_not_of(' ', end - item.data()) != std::string::npos)
      bad(name, fmt::format("shape entry '{}'", item));
    if (d != 0 && n > (std::size_t{1} << 40) / d) bad(name, "shape too large");  // no overflow below
    a.shape.push_back(d);
    n *= d;
  }
  const std::size_t width = a.dtype == "<f8" ? 8 : 4;
  const std::string_view data = bytes.substr(start + header_len);
  if (data.size() != n * width)
    bad(name, fmt::format("{} data bytes for shape {} of {}", data.size(), shape_tuple(a.shape), a.dtype));
  a.values.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (width == 8) {
      std::memcpy(&a.values[i], data.data() + 8 * i, 8);
    } else {
      float f;
      std::memcpy(&f, data.data() + 4 * i, 4);
      a.values[i] = f;
    }
  }
  return a;
}

NpyArray read_npy(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot read", path.string()));
  std::ostringstream s;
  s << in.rdbuf();
  return parse_npy(s.str(), path.string());
}

}  // namespace vrv
