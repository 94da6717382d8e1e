#include "lib/volume/metaimage_reader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

namespace vrv {
namespace {

constexpr std::size_t kMaxHeaderBytes = std::size_t{1} << 20;
// The head read to find the header: its limit and one more line of up to as many bytes.
constexpr std::size_t kHeadBytes = 2 * kMaxHeaderBytes;

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

struct Header {
  std::map<std::string, std::string, std::less<>> keys;
  std::size_t data_start = 0;  // just after the ElementDataFile line
};

// Key = value lines up to ElementDataFile, which ends the header (the data may follow).
// `bytes` is the file's head (kHeadBytes, or all of a shorter file).
Header parse_header(const std::string& bytes, const std::filesystem::path& file) {
  Header h;
  std::size_t pos = 0;
  while (pos < bytes.size()) {
    if (pos > kMaxHeaderBytes) volume_fail(file, "(header)", fmt::format("no ElementDataFile in the first {} bytes", kMaxHeaderBytes));
    std::size_t end = bytes.find('\n', pos);
    if (end == std::string::npos && bytes.size() == kHeadBytes)
      volume_fail(file, "(header)", fmt::format("a line longer than {} bytes", kHeadBytes - kMaxHeaderBytes));
    if (end == std::string::npos) end = bytes.size();
    const std::string_view line = trim(std::string_view(bytes).substr(pos, end - pos));
    pos = std::min(end + 1, bytes.size());
    if (line.empty()) continue;
    const std::size_t eq = line.find('=');
    if (eq == std::string_view::npos)
      volume_fail(file, "(header)", fmt::format("line \"{}\" is not key = value", line.substr(0, 80)));
    const std::string key(trim(line.substr(0, eq)));
    if (!h.keys.emplace(key, std::string(trim(line.substr(eq + 1)))).second)
      volume_fail(file, key, "given twice");
    if (key == "ElementDataFile") {
      h.data_start = pos;
      return h;
    }
  }
  volume_fail(file, "ElementDataFile", "missing (it ends the header)");
}

const std::string* find_any(const Header& h, std::initializer_list<std::string_view> names) {
  for (std::string_view n : names)
    if (auto it = h.keys.find(n); it != h.keys.end()) return &it->second;
  return nullptr;
}

bool boolean(const std::filesystem::path& file, std::string_view key, const std::string* text, bool fallback) {
  if (!text) return fallback;
  std::string t = *text;
  std::transform(t.begin(), t.end(), t.begin(), [](unsigned char c) { return std::tolower(c); });
  if (t == "true" || t == "1") return true;
  if (t == "false" || t == "0") return false;
  volume_fail(file, key, fmt::format("\"{}\" is not True or False", text->substr(0, 80)));
}

ScalarType element_type(const std::filesystem::path& file, const std::string* text) {
  if (!text) volume_fail(file, "ElementType", "missing");
  static const std::pair<std::string_view, ScalarType> types[] = {
      {"MET_UCHAR", ScalarType::u8},   {"MET_CHAR", ScalarType::i8},  {"MET_USHORT", ScalarType::u16},
      {"MET_SHORT", ScalarType::i16},  {"MET_UINT", ScalarType::u32}, {"MET_INT", ScalarType::i32},
      {"MET_FLOAT", ScalarType::f32},  {"MET_DOUBLE", ScalarType::f64}};
  for (const auto& [name, t] : types)
    if (*text == name) return t;
  volume_fail(file, "ElementType", fmt::format("{} not supported (MET_UCHAR to MET_INT, MET_FLOAT, MET_DOUBLE)",
                                               text->substr(0, 80)));
}

void check_header(const Header& h, const std::filesystem::path& file) {
  if (const auto* t = find_any(h, {"ObjectType"}); t && *t != "Image")
    volume_fail(file, "ObjectType", fmt::format("{} is not an Image", t->substr(0, 80)));
  const std::string* ndims = find_any(h, {"NDims"});
  if (!ndims) volume_fail(file, "NDims", "missing");
  if (header_numbers(file, "NDims", *ndims, 1)[0] != 3)
    volume_fail(file, "NDims", fmt::format("{} not supported (a 3-D scalar volume only; a time series is refused)", *ndims));
  if (const auto* c = find_any(h, {"ElementNumberOfChannels"}); c && header_numbers(file, "ElementNumberOfChannels", *c, 1)[0] != 1)
    volume_fail(file, "ElementNumberOfChannels", fmt::format("{} components not supported (one only)", *c));
  if (!boolean(file, "BinaryData", find_any(h, {"BinaryData"}), true))
    volume_fail(file, "BinaryData", "ASCII data not supported (binary only)");
}

void set_geometry(Volume& v, const Header& h, const std::filesystem::path& file) {
  std::vector<double> spacing{1, 1, 1}, offset{0, 0, 0}, matrix{1, 0, 0, 0, 1, 0, 0, 0, 1};
  if (const auto* s = find_any(h, {"ElementSpacing", "ElementSize"})) spacing = header_numbers(file, "ElementSpacing", *s, 3);
  if (const auto* s = find_any(h, {"Offset", "Position", "Origin"})) offset = header_numbers(file, "Offset", *s, 3);
  if (const auto* s = find_any(h, {"TransformMatrix", "Rotation", "Orientation"}))
    matrix = header_numbers(file, "TransformMatrix", *s, 9);
  Eigen::Matrix3d steps;
  for (int a = 0; a < 3; ++a)
    for (int w = 0; w < 3; ++w) steps(w, a) = matrix[3 * a + w] * spacing[a];
  for (int w = 0; w < 3; ++w) v.origin[w] = offset[w];
  set_axis_aligned(v, steps, file, "TransformMatrix");
}

// After the header (LOCAL) or in the detached file, at HeaderSize (-1: the data end the file);
// compressed data end at CompressedDataSize where it is given.
StoredSamples find_data(const Header& h, const std::filesystem::path& file, Volume& v, std::size_t need) {
  StoredSamples d;
  d.compressed = boolean(file, "CompressedData", find_any(h, {"CompressedData"}), false);
  const std::string& name = h.keys.find("ElementDataFile")->second;
  if (name == "LOCAL") {
    const std::uint64_t size = file_size_of(file);
    d = {file, h.data_start, size - std::min<std::uint64_t>(size, h.data_start), d.compressed};
  } else {
    if (name.rfind("LIST", 0) == 0 || name.find('%') != std::string::npos || name.empty())
      volume_fail(file, "ElementDataFile", fmt::format("\"{}\": a list or pattern of files is not supported", name.substr(0, 80)));
    d.path = file.parent_path() / name;
    v.files.push_back(d.path);
    std::uint64_t size = 0;
    try {
      size = file_size_of(d.path);
    } catch (const VolumeFileError& e) {  // named from the header that points at it
      volume_fail(file, "ElementDataFile", e.what());
    }
    double skip = 0;
    if (const auto* s = find_any(h, {"HeaderSize"})) skip = header_numbers(file, "HeaderSize", *s, 1)[0];
    if (skip == -1) skip = static_cast<double>(size - std::min<std::uint64_t>(size, need));
    if (!(skip >= 0) || skip != std::floor(skip) || skip > static_cast<double>(size))
      volume_fail(file, "HeaderSize", fmt::format("{} is not a byte offset within the data file's {} bytes", skip, size));
    d.offset = static_cast<std::uint64_t>(skip);
    d.available = size - d.offset;
  }
  if (const auto* s = find_any(h, {"CompressedDataSize"}); s && d.compressed) {
    const double c = header_numbers(file, "CompressedDataSize", *s, 1)[0];
    if (!(c >= 0) || c > static_cast<double>(d.available))
      volume_fail(file, "CompressedDataSize", fmt::format("{} bytes, but {} follow the header", *s, d.available));
    d.available = static_cast<std::uint64_t>(c);
  }
  return d;
}

}  // namespace

Volume read_metaimage(const std::filesystem::path& file, const VolumeReadOptions& options) {
  const Header h = parse_header(read_file_head(file, kHeadBytes), file);
  check_header(h, file);
  Volume v;
  const ScalarType type = element_type(file, find_any(h, {"ElementType"}));
  const std::string* dim = find_any(h, {"DimSize"});
  if (!dim) volume_fail(file, "DimSize", "missing");
  std::array<std::int64_t, 3> dims{};
  const auto d = header_numbers(file, "DimSize", *dim, 3);
  for (int a = 0; a < 3; ++a) {
    if (d[a] != std::floor(d[a]) || !(std::abs(d[a]) < 1e15)) volume_fail(file, "DimSize", fmt::format("{} is not a whole number", d[a]));
    dims[a] = static_cast<std::int64_t>(d[a]);
  }
  v.dims = checked_dims(file, "DimSize", dims);
  set_geometry(v, h, file);
  check_budget(file, "DimSize", v, type, 0, options);
  v.files.push_back(file);
  const bool big_endian = boolean(file, "ElementByteOrderMSB", find_any(h, {"ElementByteOrderMSB", "BinaryDataByteOrderMSB"}), false);
  const std::size_t count = static_cast<std::size_t>(v.dims[0]) * v.dims[1] * v.dims[2];
  const StoredSamples place = find_data(h, file, v, count * scalar_bytes(type));
  v.samples = read_stored_samples(place, type, count, big_endian, file, place.compressed ? "CompressedData" : "(data)");
  return v;
}

}  // namespace vrv
