#include "lib/volume/vti_reader.h"

// libb64's C header declares no C linkage.
extern "C" {
#include <b64/cdecode.h>
}
#include <pugixml.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

namespace vrv {
namespace {

using Path = std::filesystem::path;

ScalarType array_type(const Path& file, std::string_view t) {
  static const std::pair<std::string_view, ScalarType> types[] = {
      {"UInt8", ScalarType::u8},   {"Int8", ScalarType::i8},    {"UInt16", ScalarType::u16},
      {"Int16", ScalarType::i16},  {"UInt32", ScalarType::u32}, {"Int32", ScalarType::i32},
      {"Float32", ScalarType::f32}, {"Float64", ScalarType::f64}};
  for (const auto& [name, s] : types)
    if (t == name) return s;
  volume_fail(file, "DataArray.type", fmt::format("\"{}\" not supported (UInt8 to Int32, Float32, Float64)", t.substr(0, 80)));
}

// base64 text (whitespace ignored) in segments that each end in their own '=' padding: VTK
// encodes a compressed array's header apart from its blocks, so padding may sit mid-stream,
// where libb64's decoder (which skips '=') would lose the alignment.
std::string base64_decode(std::string_view text) {
  std::string clean;
  clean.reserve(text.size());
  for (char c : text)
    if (!std::isspace(static_cast<unsigned char>(c))) clean.push_back(c);
  std::string out;
  std::size_t pos = 0;
  while (pos < clean.size()) {
    std::size_t end = clean.find('=', pos);
    end = end == std::string::npos ? clean.size() : clean.find_first_not_of('=', end);
    if (end == std::string::npos) end = clean.size();
    const std::size_t len = std::min<std::size_t>(end - pos, INT_MAX / 4 * 3);
    std::string chunk(len / 4 * 3 + 3, '\0');
    base64_decodestate state;
    base64_init_decodestate(&state);
    const int n = base64_decode_block(clean.data() + pos, static_cast<int>(len), chunk.data(), &state);
    out.append(chunk.data(), static_cast<std::size_t>(n));
    pos += len;
  }
  return out;
}

struct Encoding {
  bool big_endian = false;
  std::size_t header_bytes = 4;  // UInt32 or UInt64
  bool zlib = false;
};

std::uint64_t header_value(const Encoding& e, const unsigned char* p) {
  std::uint64_t v = 0;
  for (std::size_t b = 0; b < e.header_bytes; ++b) {
    const std::size_t byte = e.big_endian ? e.header_bytes - 1 - b : b;
    v |= static_cast<std::uint64_t>(p[byte]) << (8 * b);
  }
  return v;
}

// The array's bytes from a binary stream at `p` (header, then data): `need` bytes expected.
std::vector<unsigned char> binary_array(const Path& file, const Encoding& e, const unsigned char* p,
                                        std::size_t size, std::size_t need) {
  const std::size_t h = e.header_bytes;
  auto short_of = [&](std::size_t bytes) {
    if (bytes > size) volume_fail(file, "DataArray", fmt::format("truncated: {} bytes, the array's header needs {}", size, bytes));
  };
  auto truncated = [&] { volume_fail(file, "DataArray", fmt::format("truncated: {} bytes, fewer than the array's header states", size)); };
  if (!e.zlib) {
    short_of(h);
    const std::uint64_t n = header_value(e, p);
    if (n != need) volume_fail(file, "DataArray", fmt::format("{} bytes of data, the extent and type need {}", n, need));
    short_of(h + need);
    return {p + h, p + h + need};
  }
  short_of(3 * h);
  const std::uint64_t blocks = header_value(e, p), block = header_value(e, p + h), last = header_value(e, p + 2 * h);
  if (blocks > size / h) truncated();
  short_of((3 + blocks) * h);
  const std::uint64_t last_size = last == 0 ? block : last;
  if (blocks == 0 ? need != 0 : (block == 0 || (blocks - 1) > need / block || (blocks - 1) * block + last_size != need))
    volume_fail(file, "DataArray", fmt::format("{} compressed blocks of {} bytes (last {}) do not make the {} bytes needed",
                                               blocks, block, last, need));
  std::vector<unsigned char> out;
  out.reserve(need);
  std::size_t at = (3 + blocks) * h;
  for (std::uint64_t b = 0; b < blocks; ++b) {
    const std::uint64_t c = header_value(e, p + (3 + b) * h);
    if (c > size - at) truncated();
    const auto raw = inflate_exactly(p + at, c, b + 1 == blocks ? last_size : block, file,
                                     fmt::format("DataArray block {}", b));
    out.insert(out.end(), raw.begin(), raw.end());
    at += c;
  }
  return out;
}

template <class T>
void parse_ascii(const Path& file, std::string_view text, std::size_t count, ScalarType t, std::vector<T>& out) {
  out.reserve(count);
  const char* p = text.data();
  const char* end = p + text.size();
  while (true) {
    while (p < end && std::isspace(static_cast<unsigned char>(*p))) ++p;
    if (p == end) break;
    T x{};
    const auto [next, ec] = std::from_chars(p, end, x);
    if (ec != std::errc() || out.size() == count)
      volume_fail(file, "DataArray", out.size() == count ? fmt::format("more than {} ascii values", count)
                                                         : fmt::format("ascii value {} is not a {}", out.size(), to_string(t)));
    out.push_back(x);
    p = next;
  }
  if (out.size() != count) volume_fail(file, "DataArray", fmt::format("{} ascii values, the extent needs {}", out.size(), count));
}

VolumeSamples ascii_array(const Path& file, ScalarType t, std::string_view text, std::size_t count) {
  static const unsigned char none = 0;
  VolumeSamples s = samples_from_bytes(t, &none, 0, false);
  std::visit([&](auto& v) { parse_ascii(file, text, count, t, v); }, s);
  return s;
}

Encoding encoding(const Path& file, const pugi::xml_node& root) {
  Encoding e;
  const std::string_view order = root.attribute("byte_order").as_string("LittleEndian");
  if (order == "BigEndian") e.big_endian = true;
  else if (order != "LittleEndian") volume_fail(file, "byte_order", fmt::format("\"{}\" unknown", order.substr(0, 80)));
  const std::string_view header = root.attribute("header_type").as_string("UInt32");
  if (header == "UInt64") e.header_bytes = 8;
  else if (header != "UInt32") volume_fail(file, "header_type", fmt::format("\"{}\" not supported (UInt32, UInt64)", header.substr(0, 80)));
  const std::string_view compressor = root.attribute("compressor").as_string("");
  if (compressor == "vtkZLibDataCompressor") e.zlib = true;
  else if (!compressor.empty())
    volume_fail(file, "compressor", fmt::format("{} not supported (vtkZLibDataCompressor or none)", compressor.substr(0, 80)));
  return e;
}

// The file split where appended raw data begin: raw bytes are no XML, so pugixml sees the text
// before them with the elements closed.
struct Split {
  std::string xml;
  std::optional<std::size_t> appended;  // offset of the byte after '_' in the file
};

Split split_appended(const std::string& bytes) {
  const std::size_t tag = bytes.find("<AppendedData");
  if (tag == std::string::npos) return {bytes, std::nullopt};
  const std::size_t close = bytes.find('>', tag);
  const std::size_t underscore = close == std::string::npos ? std::string::npos : bytes.find('_', close);
  if (underscore == std::string::npos) return {bytes, std::nullopt};
  return {bytes.substr(0, underscore) + "</AppendedData></VTKFile>", underscore + 1};
}

}  // namespace

Volume read_vti(const Path& file, const VolumeReadOptions& options) {
  const std::size_t max_bytes = static_cast<std::size_t>(std::max<std::int64_t>(options.max_bytes, 0));
  // ascii text takes up to ~25 characters a value: the file cap is generous.
  const std::string bytes = read_file_bytes(file, 4 * max_bytes + (std::size_t{1} << 20));
  const Split split = split_appended(bytes);
  pugi::xml_document doc;
  const pugi::xml_parse_result parsed = doc.load_buffer(split.xml.data(), split.xml.size());
  if (!parsed) volume_fail(file, "(xml)", fmt::format("offset {}: {}", parsed.offset, parsed.description()));
  const pugi::xml_node root = doc.child("VTKFile");
  if (!root || std::string_view(root.attribute("type").as_string()) != "ImageData")
    volume_fail(file, "VTKFile", "not a VTKFile of type ImageData");
  const Encoding e = encoding(file, root);
  const pugi::xml_node image = root.child("ImageData");
  if (!image) volume_fail(file, "ImageData", "missing");
  const auto extent = header_numbers(file, "WholeExtent", image.attribute("WholeExtent").as_string(), 6);
  const auto origin = header_numbers(file, "Origin", image.attribute("Origin").as_string("0 0 0"), 3);
  const auto spacing = header_numbers(file, "Spacing", image.attribute("Spacing").as_string("1 1 1"), 3);
  const auto direction = header_numbers(file, "Direction", image.attribute("Direction").as_string("1 0 0 0 1 0 0 0 1"), 9);
  const pugi::xml_node piece = image.child("Piece");
  if (!piece) volume_fail(file, "Piece", "missing");
  if (piece.next_sibling("Piece")) volume_fail(file, "Piece", "several pieces not supported (one piece only)");
  if (piece.attribute("Extent") && header_numbers(file, "Piece.Extent", piece.attribute("Extent").as_string(), 6) != extent)
    volume_fail(file, "Piece.Extent", "differs from the WholeExtent (one piece covering it only)");

  Volume v;
  std::array<std::int64_t, 3> dims{};
  for (int a = 0; a < 3; ++a) {
    const double d = extent[2 * a + 1] - extent[2 * a] + 1;
    if (extent[2 * a] != std::floor(extent[2 * a]) || extent[2 * a + 1] != std::floor(extent[2 * a + 1]) || !(std::abs(d) < 1e15))
      volume_fail(file, "WholeExtent", "not whole numbers");
    dims[a] = static_cast<std::int64_t>(d);
  }
  v.dims = checked_dims(file, "WholeExtent", dims);
  Eigen::Matrix3d steps;
  for (int w = 0; w < 3; ++w)
    for (int a = 0; a < 3; ++a) steps(w, a) = direction[3 * w + a] * spacing[a];
  set_axis_aligned(v, steps, file, "Direction");
  const Eigen::Vector3d first(extent[0], extent[2], extent[4]);
  v.origin = Eigen::Vector3d(origin[0], origin[1], origin[2]) + steps * first;
  v.files.push_back(file);

  const pugi::xml_node points = piece.child("PointData");
  pugi::xml_node array;
  if (points) {
    const std::string_view scalars = points.attribute("Scalars").as_string("");
    array = scalars.empty() ? points.child("DataArray") : points.find_child_by_attribute("DataArray", "Name", std::string(scalars).c_str());
  }
  if (!array) {
    if (piece.child("CellData").child("DataArray"))
      volume_fail(file, "CellData", "cell data not supported (point data only)");
    volume_fail(file, "PointData", "no DataArray");
  }
  const ScalarType type = array_type(file, array.attribute("type").as_string());
  if (const int c = array.attribute("NumberOfComponents").as_int(1); c != 1)
    volume_fail(file, "NumberOfComponents", fmt::format("{} components not supported (one only)", c));
  check_budget(file, "WholeExtent", v.dims, type, options);
  const std::size_t count = static_cast<std::size_t>(v.dims[0]) * v.dims[1] * v.dims[2];
  const std::size_t need = count * scalar_bytes(type);

  const std::string_view format = array.attribute("format").as_string("");
  if (format == "ascii") {
    v.samples = ascii_array(file, type, array.child_value(), count);
    return v;
  }
  std::vector<unsigned char> raw;
  if (format == "binary") {
    const std::string decoded = base64_decode(array.child_value());
    raw = binary_array(file, e, reinterpret_cast<const unsigned char*>(decoded.data()), decoded.size(), need);
  } else if (format == "appended") {
    const pugi::xml_node appended = root.child("AppendedData");
    if (!appended || !split.appended) volume_fail(file, "AppendedData", "missing");
    const double offset = array.attribute("offset").as_double(-1);
    const std::string_view enc = appended.attribute("encoding").as_string("raw");
    std::string block;
    if (enc == "raw") {
      const std::size_t end = bytes.rfind("</AppendedData>");
      block = bytes.substr(*split.appended, end == std::string::npos || end < *split.appended ? std::string::npos : end - *split.appended);
    } else if (enc == "base64") {
      const std::size_t end = bytes.find('<', *split.appended);
      block = base64_decode(std::string_view(bytes).substr(*split.appended, end == std::string::npos ? std::string::npos : end - *split.appended));
    } else {
      volume_fail(file, "AppendedData.encoding", fmt::format("\"{}\" unknown (raw or base64)", enc.substr(0, 80)));
    }
    if (!(offset >= 0) || offset != std::floor(offset) || offset > static_cast<double>(block.size()))
      volume_fail(file, "DataArray.offset", fmt::format("{} is not within the {} appended bytes", array.attribute("offset").as_string(), block.size()));
    const std::size_t at = static_cast<std::size_t>(offset);
    raw = binary_array(file, e, reinterpret_cast<const unsigned char*>(block.data()) + at, block.size() - at, need);
  } else {
    volume_fail(file, "DataArray.format", fmt::format("\"{}\" unknown (ascii, binary or appended)", format.substr(0, 80)));
  }
  v.samples = samples_from_bytes(type, raw.data(), count, e.big_endian);
  return v;
}

}  // namespace vrv
