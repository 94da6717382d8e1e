#include "lib/io/image_structure.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <fstream>
#include <optional>
#include <system_error>

#include <fmt/format.h>

namespace vrv {
namespace {

constexpr std::string_view kPng = "\x89PNG\r\n\x1a\n";
constexpr std::string_view kExr = "\x76\x2f\x31\x01";
constexpr std::uint64_t kLargestPngChunk = (std::uint64_t{1} << 31) - 1;  // the PNG specification's
constexpr std::uint64_t kExrHeaderRead = std::uint64_t{1} << 24;
constexpr std::uint32_t kExrMultipart = 0x1000;  // version flag: several headers, an empty one last

std::uint32_t u32(std::string_view b, bool big_endian) {
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= std::uint32_t{static_cast<unsigned char>(b[big_endian ? 3 - i : i])} << (8 * i);
  return v;
}

std::string printable(std::string_view text) {
  std::string s(text.substr(0, 64));
  for (char& c : s)
    if (!std::isprint(static_cast<unsigned char>(c))) c = '?';
  return s;
}

// A PNG of `size` bytes, `header(at, out)` reading the 8 bytes at `at`.  A chunk: length (4 bytes),
// type (4), data (length), CRC (4).  A header cut short is left to libpng, which reports it.
template <class Header>
std::string walk_png(std::uint64_t size, Header&& header) {
  std::uint64_t at = kPng.size();
  char h[8];
  while (at + 8 <= size) {
    if (!header(at, h)) return {};
    const std::uint64_t length = u32(std::string_view(h, 4), true);
    const std::string type = printable(std::string_view(h + 4, 4));
    const std::uint64_t left = size - at - 8;
    if (length > kLargestPngChunk)
      return fmt::format("PNG chunk '{}' at byte {} claims {} bytes, above PNG's 2^31 - 1 (damaged)", type, at, length);
    if (length + 4 > left)
      return fmt::format("PNG chunk '{}' at byte {} claims {} bytes, {} are left (damaged or truncated)", type, at,
                         length, left >= 4 ? left - 4 : 0);
    if (type == "IEND") break;
    at += 12 + length;
  }
  return {};
}

// The bytes of a type OpenEXR's reader takes whatever size the attribute declares; 0 for a type it
// reads by the declared size (string, stringvector, floatvector, preview, an unknown type).
std::uint64_t exr_fixed_size(std::string_view type) {
  struct Fixed {
    std::string_view type;
    std::uint64_t size;
  };
  static constexpr Fixed kFixed[] = {
      {"box2i", 16},       {"box2f", 16},        {"v2i", 8},       {"v2f", 8},        {"v2d", 16},
      {"v3i", 12},         {"v3f", 12},          {"v3d", 24},      {"m33f", 36},      {"m33d", 72},
      {"m44f", 64},        {"m44d", 128},        {"int", 4},       {"float", 4},      {"double", 8},
      {"compression", 1},  {"lineOrder", 1},     {"envmap", 1},    {"deepImageState", 1},
      {"tiledesc", 9},     {"rational", 8},      {"timecode", 8},  {"keycode", 28},   {"chromaticities", 32}};
  for (const Fixed& f : kFixed)
    if (f.type == type) return f.size;
  return 0;
}

// The bytes a channel list at `value` takes as OpenEXR reads it: entries (name, 0, 16 bytes) until
// an empty name; nullopt when it does not end within `bytes`.
std::optional<std::uint64_t> exr_channel_list_size(std::string_view bytes, std::size_t value) {
  for (std::size_t p = value; p < bytes.size();) {
    if (bytes[p] == 0) return p + 1 - value;
    const std::size_t name_end = bytes.find('\0', p);
    if (name_end == std::string_view::npos) break;
    p = name_end + 1 + 16;
  }
  return std::nullopt;
}

}  // namespace

std::optional<std::uint64_t> exr_value_extent(std::string_view type, std::string_view bytes, std::uint64_t value,
                                              std::uint64_t declared) {
  if (type == "chlist") return exr_channel_list_size(bytes, value);
  // OpenEXR 3.1.5 reads a float vector's whole floats only, and an ID manifest's 8-byte size
  // before its declared size - 4 bytes of data (ImfIDManifestAttribute.cpp: 4 more than declared).
  if (type == "floatvector") return declared / 4 * 4;
  if (type == "idmanifest" && declared >= 4) return declared + 4;
  const std::uint64_t fixed = exr_fixed_size(type);
  return fixed ? fixed : declared;
}

// An EXR's header(s): after magic and version, attributes (name, type, int32 size, value) until an
// empty name; a multipart file repeats that, an empty header last.  What is cut off is left to
// OpenEXR.  The walk steps from attribute to attribute as OpenEXR does (exr_value_extent), not by
// the declared sizes: where a size is wrong they part ways, and OpenEXR would then take text for a size.
void walk_exr_attributes(std::string_view bytes, std::uint64_t size,
                         const std::function<bool(const ExrAttribute&)>& visit) {
  if (bytes.size() < 8 || bytes.substr(0, kExr.size()) != kExr) return;
  const bool multipart = u32(bytes.substr(4, 4), false) & kExrMultipart;
  std::size_t at = 8;
  while (at < bytes.size() && bytes[at] != 0) {
    while (at < bytes.size() && bytes[at] != 0) {
      const std::size_t name_end = bytes.find('\0', at);
      const std::size_t type_end = name_end == std::string_view::npos ? name_end : bytes.find('\0', name_end + 1);
      if (type_end == std::string_view::npos || type_end + 5 > bytes.size()) return;
      const ExrAttribute a{bytes.substr(at, name_end - at), bytes.substr(name_end + 1, type_end - name_end - 1), at,
                           type_end + 5, u32(bytes.substr(type_end + 1, 4), false)};
      if (!visit(a) || a.length > size - a.value) return;
      const std::optional<std::uint64_t> extent = exr_value_extent(a.type, bytes, a.value, a.length);
      if (!extent) return;  // a channel list running off the end: OpenEXR says so, allocating nothing
      at = a.value + *extent;
    }
    ++at;  // the header's terminating empty name
    if (!multipart) break;
  }
}

namespace {

std::string walk_exr(std::string_view bytes, std::uint64_t size) {
  std::string problem;
  walk_exr_attributes(bytes, size, [&](const ExrAttribute& a) {
    if (a.length > size - a.value)
      problem = fmt::format("EXR attribute '{}' at byte {} claims {} bytes, {} are left (damaged or truncated)",
                            printable(a.name), a.at, static_cast<std::int32_t>(a.length), size - a.value);
    return problem.empty();
  });
  return problem;
}

}  // namespace

std::string image_structure_problem(std::string_view bytes) {
  if (bytes.substr(0, kPng.size()) == kPng)
    return walk_png(bytes.size(), [&](std::uint64_t at, char* out) {
      bytes.copy(out, 8, at);
      return true;
    });
  if (bytes.substr(0, kExr.size()) == kExr) return walk_exr(bytes, bytes.size());
  return {};
}

std::string image_file_structure_problem(const std::filesystem::path& file) {
  std::error_code ec;
  const std::uint64_t size = std::filesystem::file_size(file, ec);
  std::ifstream in(file, std::ios::binary);
  char head[8] = {};
  if (ec || !in.read(head, sizeof head)) return {};
  const std::string_view start(head, sizeof head);
  if (start == kPng)
    return walk_png(size, [&](std::uint64_t at, char* out) {
      in.seekg(static_cast<std::streamoff>(at));
      return static_cast<bool>(in.read(out, 8));
    });
  if (start.substr(0, kExr.size()) != kExr) return {};
  std::string header(std::min(size, kExrHeaderRead), '\0');
  in.seekg(0);
  in.read(header.data(), static_cast<std::streamsize>(header.size()));
  header.resize(static_cast<std::size_t>(in.gcount()));
  return walk_exr(header, size);
}

}  // namespace vrv
