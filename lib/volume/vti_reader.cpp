#include "lib/volume/vti_reader.h"

// libb64's C header declares no C linkage.
extern "C" {
#include <b64/cdecode.h>
}
#include <pugixml.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <optional>
#include <span>
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

// Decodes base64 text (whitespace ignored) in place and returns the decoded length: the text is
// this reader's own buffer and the decoded bytes are shorter, so no second copy is held.  The
// text comes in segments that each end in their own '=' padding: VTK encodes a compressed
// array's header apart from its blocks, so padding may sit mid-stream, where libb64's decoder
// (which skips '=') would lose the alignment.  Each segment is decoded a few megabytes at a time
// through a buffer and written back behind where it is read.
std::size_t base64_decode_in_place(char* text, std::size_t size) {
  const std::size_t clean = static_cast<std::size_t>(
      std::remove_if(text, text + size, [](char c) { return std::isspace(static_cast<unsigned char>(c)); }) - text);
  const std::string_view all(text, clean);
  // Characters, a multiple of 4: no characters are pending between a segment's chunks, so a
  // chunk's bytes and libb64's partial byte fit the buffer.
  constexpr std::size_t kChunk = std::size_t{1} << 22;
  static_assert(kChunk % 4 == 0);
  std::vector<char> buffer(std::min(clean, kChunk) / 4 * 3 + 3);
  std::size_t written = 0, pos = 0;
  while (pos < clean) {
    std::size_t end = all.find('=', pos);
    end = end == std::string_view::npos ? clean : all.find_first_not_of('=', end);
    if (end == std::string_view::npos) end = clean;
    base64_decodestate state;
    base64_init_decodestate(&state);
    for (; pos < end;) {
      const std::size_t len = std::min(end - pos, kChunk);
      const int n = base64_decode_block(text + pos, static_cast<int>(len), buffer.data(), &state);
      std::memcpy(text + written, buffer.data(), static_cast<std::size_t>(n));  // written <= pos
      written += static_cast<std::size_t>(n);
      pos += len;
    }
  }
  return written;
}

bool is_base64_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '+' || c == '/'; }

// Appended base64 text decoded as it is read from the file, a megabyte of text at a time, up to
// the '<' that ends it: the array's stream without its text held.  Each run of '=' padding ends a
// segment (VTK encodes a compressed array's header apart from its blocks); whitespace and '='
// are skipped by libb64's decoder.
class Base64FileStream {
 public:
  Base64FileStream(const Path& file, std::uint64_t offset, std::uint64_t end)
      : in_(file, std::ios::binary), left_(end - std::min(end, offset)) {
    in_.seekg(static_cast<std::streamoff>(offset));
    base64_init_decodestate(&state_);
  }
  std::uint64_t given() const { return given_; }
  // The next n decoded bytes into out (nullptr: skipped); false when the text ends first.
  bool next(unsigned char* out, std::size_t n) {
    while (n > 0) {
      if (at_ == bytes_.size() && !refill()) return false;
      const std::size_t k = std::min(n, bytes_.size() - at_);
      if (out) std::memcpy(out, bytes_.data() + at_, k), out += k;
      at_ += k, n -= k, given_ += k;
    }
    return true;
  }

 private:
  // Decodes the next megabyte of text that holds any bytes; false at the end of the text.
  bool refill() {
    while (left_ > 0)
      if (decode_next_chunk()) return true;
    return false;
  }
  bool decode_next_chunk() {
    text_.resize(static_cast<std::size_t>(std::min<std::uint64_t>(left_, std::size_t{1} << 20)));
    in_.read(text_.data(), static_cast<std::streamsize>(text_.size()));
    if (static_cast<std::size_t>(in_.gcount()) != text_.size()) {
      left_ = 0;  // a read error: the array ends here (named as truncated)
      return false;
    }
    left_ -= text_.size();
    if (const auto end = std::find(text_.begin(), text_.end(), '<'); end != text_.end()) {
      text_.erase(end, text_.end());
      left_ = 0;
    }
    // At most 3/4 of the text and of up to 3 characters pending from the last chunk, and the
    // partial byte libb64 writes past what it counts.
    bytes_.resize(text_.size() / 4 * 3 + 6);
    std::size_t made = 0;
    for (std::size_t pos = 0; pos < text_.size();) {
      if (after_padding_) {  // a new segment starts at the next base64 character
        while (pos < text_.size() && !is_base64_char(text_[pos])) ++pos;
        if (pos == text_.size()) break;
        base64_init_decodestate(&state_);
        after_padding_ = false;
      }
      const auto pad = static_cast<std::size_t>(std::find(text_.begin() + pos, text_.end(), '=') - text_.begin());
      made += static_cast<std::size_t>(base64_decode_block(text_.data() + pos, static_cast<int>(pad - pos),
                                                           reinterpret_cast<char*>(bytes_.data()) + made, &state_));
      after_padding_ = pad < text_.size();
      pos = pad;
    }
    bytes_.resize(made);
    at_ = 0;
    return made > 0;
  }

  std::ifstream in_;
  std::uint64_t left_;
  std::vector<char> text_;
  std::vector<unsigned char> bytes_;
  std::size_t at_ = 0;
  std::uint64_t given_ = 0;
  base64_decodestate state_;
  bool after_padding_ = false;
};

// Where an array's binary stream (its header, then data) is: decoded in memory (inline base64
// arrays), in the file (appended raw data, read from one open stream into the samples) or
// decoded from the file's appended base64 text as it is read.  Read in order: header, block
// sizes, blocks.
struct ArrayBytes {
  std::string_view memory;
  mutable std::ifstream file_data;  // appended raw data from file_offset, file_available bytes
  std::uint64_t file_offset = 0, file_available = 0;
  mutable std::uint64_t file_at = 0;  // where file_data stands (reads in order need no seek)
  Base64FileStream* base64 = nullptr;
  std::uint64_t base64_bound = 0;  // decoded bytes the text can hold at most

  bool in_file() const { return file_data.is_open(); }
  std::uint64_t size() const { return in_file() ? file_available : base64 ? base64_bound : memory.size(); }
  void read(const Path& file, std::uint64_t at, unsigned char* out, std::size_t n) const {
    if (in_file()) {
      if (file_at != file_offset + at) file_data.seekg(static_cast<std::streamoff>(file_offset + at));
      file_data.read(reinterpret_cast<char*>(out), static_cast<std::streamsize>(n));
      file_at = file_offset + at + n;
      if (!file_data || static_cast<std::size_t>(file_data.gcount()) != n)
        volume_fail(file, "AppendedData", fmt::format("cannot read {} bytes from offset {} (truncated or damaged)", n,
                                                      file_offset + at));
      return;
    }
    if (!base64) return void(std::memcpy(out, memory.data() + at, n));
    if (!base64->next(nullptr, at - std::min(at, base64->given())) || !base64->next(out, n))
      volume_fail(file, "AppendedData", fmt::format("truncated: the base64 data end before byte {} of the array", at + n));
  }
  // One zlib block of n bytes at `at`, inflated to `expected` bytes at `out` (from the file or
  // the base64 stream a megabyte at a time).
  void inflate(const Path& file, std::uint64_t at, std::uint64_t n, unsigned char* out, std::size_t expected,
               std::string_view what) const {
    if (!in_file() && !base64)
      return inflate_into(reinterpret_cast<const unsigned char*>(memory.data()) + at, static_cast<std::size_t>(n), out,
                          expected, file, what);
    std::vector<unsigned char> chunk;
    std::uint64_t given = 0;
    const auto next = [&] {
      chunk.resize(static_cast<std::size_t>(std::min<std::uint64_t>(n - given, std::size_t{1} << 20)));
      read(file, at + given, chunk.data(), chunk.size());
      given += chunk.size();
      return std::span<const unsigned char>(chunk);
    };
    inflate_chunks_into(static_cast<std::size_t>(n), next, out, expected, file, what);
  }
};

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

std::uint64_t header_value(const Path& file, const Encoding& e, const ArrayBytes& src, std::uint64_t at) {
  unsigned char p[8];
  src.read(file, at, p, e.header_bytes);
  return header_value(e, p);
}

// The array's `need` bytes into `out`, from its binary stream (header, then data, raw or in
// zlib blocks).  The blocks' size table is held while they are inflated: more than
// `table_budget` bytes of it are refused.
void binary_array(const Path& file, const Encoding& e, const ArrayBytes& src, unsigned char* out, std::size_t need,
                  std::uint64_t table_budget) {
  const std::uint64_t size = src.size();
  const std::size_t h = e.header_bytes;
  auto short_of = [&](std::uint64_t bytes) {
    if (bytes > size) volume_fail(file, "DataArray", fmt::format("truncated: {} bytes, the array's header needs {}", size, bytes));
  };
  auto truncated = [&] { volume_fail(file, "DataArray", fmt::format("truncated: {} bytes, fewer than the array's header states", size)); };
  if (!e.zlib) {
    short_of(h);
    const std::uint64_t n = header_value(file, e, src, 0);
    if (n != need) volume_fail(file, "DataArray", fmt::format("{} bytes of data, the extent and type need {}", n, need));
    short_of(h + need);
    return src.read(file, h, out, need);
  }
  short_of(3 * h);
  const std::uint64_t blocks = header_value(file, e, src, 0), block = header_value(file, e, src, h), last = header_value(file, e, src, 2 * h);
  if (blocks > size / h) truncated();
  short_of((3 + blocks) * h);
  const std::uint64_t last_size = last == 0 ? block : last;
  if (blocks == 0 ? need != 0 : (block == 0 || (blocks - 1) > need / block || (blocks - 1) * block + last_size != need))
    volume_fail(file, "DataArray", fmt::format("{} compressed blocks of {} bytes (last {}) do not make the {} bytes needed",
                                               blocks, block, last, need));
  if (blocks * h > table_budget)
    volume_fail(file, "DataArray", fmt::format("{} compressed blocks of {} bytes: their {}-byte size table is more than "
                                               "the {} bytes --max-memory leaves beside the samples", blocks, block,
                                               blocks * h, table_budget));
  std::vector<unsigned char> sizes(static_cast<std::size_t>(blocks * h));
  src.read(file, 3 * h, sizes.data(), sizes.size());
  std::uint64_t at = (3 + blocks) * h;
  for (std::uint64_t b = 0; b < blocks; ++b) {
    const std::uint64_t c = header_value(e, sizes.data() + b * h);
    if (c > size - at) truncated();
    src.inflate(file, at, c, out + b * block, b + 1 == blocks ? last_size : block, fmt::format("DataArray block {}", b));
    at += c;
  }
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

// The file's text up to where its appended data begin (just after the '_' that follows
// <AppendedData ...>), read a megabyte at a time, with the elements closed: appended raw bytes
// are no XML, and neither raw nor base64 appended data are held with the document.  The whole
// file when it has no appended data (its arrays are inline).  The text is held while the array
// is read, so text longer than the memory budget alone is refused as it is read.
struct VtiText {
  std::string xml;
  std::optional<std::uint64_t> appended;  // offset of the byte after '_' in the file
};

VtiText read_vti_text(const Path& file, std::size_t max_bytes) {
  const std::uint64_t size = file_size_of(file);  // refuses a directory or an unopenable file
  std::ifstream in(file, std::ios::binary);
  if (!in) volume_fail(file, "(file)", "cannot open");
  const auto refuse_longer = [&](std::size_t text) {
    if (text > max_bytes)
      volume_fail(file, "(file)", fmt::format("its XML text, held while its arrays are read, is longer than the {} "
                                              "bytes allowed (--max-memory)", max_bytes));
  };
  VtiText t;
  constexpr std::string_view kTag = "<AppendedData";
  // Each search resumes where the last one stopped (the file is scanned once).
  std::size_t tag = std::string::npos, close = std::string::npos, from = 0;
  std::vector<char> chunk(std::size_t{1} << 20);
  while (in.read(chunk.data(), static_cast<std::streamsize>(chunk.size())) || in.gcount() > 0) {
    t.xml.append(chunk.data(), static_cast<std::size_t>(in.gcount()));
    if (tag == std::string::npos) {
      tag = t.xml.find(kTag, from);
      from = tag == std::string::npos ? t.xml.size() - std::min(t.xml.size(), kTag.size()) : tag;
    }
    if (tag != std::string::npos && close == std::string::npos) {
      close = t.xml.find('>', from);
      if (close != std::string::npos) from = close;
    }
    const std::size_t underscore = close == std::string::npos ? std::string::npos : t.xml.find('_', from);
    if (underscore != std::string::npos) {
      refuse_longer(underscore);
      t.appended = underscore + 1;
      t.xml.resize(underscore);
      t.xml += "</AppendedData></VTKFile>";
      t.xml.shrink_to_fit();
      return t;
    }
    refuse_longer(t.xml.size());
    if (tag != std::string::npos) from = t.xml.size();  // no '>' or '_' up to here
    if (tag == std::string::npos && t.xml.size() == chunk.size())  // inline arrays, as a rule: all of the file
      t.xml.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(size, max_bytes + 1)));
  }
  if (in.bad()) volume_fail(file, "(file)", "read error");
  return t;
}

// Where the appended data end: at the last </AppendedData> (raw bytes may contain the tag; the
// closing one is found from the end of the file, a megabyte at a time), else at the end of the
// file.
std::uint64_t appended_end(const Path& file, std::uint64_t appended) {
  constexpr std::string_view kClose = "</AppendedData>";
  const std::uint64_t size = file_size_of(file);
  std::string window;
  for (std::uint64_t end = size; end > appended;) {
    const std::uint64_t start = end - std::min<std::uint64_t>(end - appended, std::uint64_t{1} << 20);
    // The window runs past `end` by the tag's length less one, so a tag across windows is found.
    const std::uint64_t stop = std::min(size, end + kClose.size() - 1);
    window.resize(static_cast<std::size_t>(stop - start));
    read_file_range(file, start, reinterpret_cast<unsigned char*>(window.data()), window.size());
    if (const std::size_t at = window.rfind(kClose); at != std::string::npos) return start + at;
    end = start;
  }
  return size;
}

// The array's stream: in the inline text (decoded in place), in the file (appended raw), or
// decoded from the appended base64 text as it is read (`stream`).  An appended array's offset
// counts bytes of the appended data as stored: raw bytes, or base64 characters (VTK encodes
// each array apart and seeks to it in the file).
ArrayBytes array_bytes(const Path& file, const pugi::xml_node& root, const pugi::xml_node& array,
                       std::string_view format, const VtiText& t, std::optional<Base64FileStream>& stream) {
  if (format == "binary") {
    // The document was parsed in place (load_buffer_inplace): its text is this reader's buffer.
    char* inline_text = const_cast<char*>(array.child_value());
    ArrayBytes bytes;
    bytes.memory = std::string_view(inline_text, base64_decode_in_place(inline_text, std::strlen(inline_text)));
    return bytes;
  }
  const pugi::xml_node appended = root.child("AppendedData");
  if (!appended || !t.appended) volume_fail(file, "AppendedData", "missing");
  const double offset = array.attribute("offset").as_double(-1);
  const std::string_view enc = appended.attribute("encoding").as_string("raw");
  if (enc != "raw" && enc != "base64")
    volume_fail(file, "AppendedData.encoding", fmt::format("\"{}\" unknown (raw or base64)", enc.substr(0, 80)));
  const std::uint64_t end = appended_end(file, *t.appended), stored = end - *t.appended;
  if (!(offset >= 0) || offset != std::floor(offset) || offset > static_cast<double>(stored))
    volume_fail(file, "DataArray.offset", fmt::format("{} is not within the {} appended bytes", array.attribute("offset").as_string(), stored));
  const auto at = *t.appended + static_cast<std::uint64_t>(offset);
  ArrayBytes bytes;
  if (enc == "raw") {
    bytes.file_data.open(file, std::ios::binary);
    if (!bytes.in_file()) volume_fail(file, "(file)", "cannot open");
    bytes.file_offset = at, bytes.file_available = end - at;
  } else {
    bytes.base64 = &stream.emplace(file, at, end);
    bytes.base64_bound = (end - at) / 4 * 3 + 3;
  }
  return bytes;
}

}  // namespace

Volume read_vti(const Path& file, const VolumeReadOptions& options) {
  const std::size_t max_bytes = static_cast<std::size_t>(std::max<std::int64_t>(options.max_bytes, 0));
  VtiText text = read_vti_text(file, max_bytes);
  pugi::xml_document doc;
  const pugi::xml_parse_result parsed = doc.load_buffer_inplace(text.xml.data(), text.xml.size());
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
  const std::string_view format = array.attribute("format").as_string("");
  if (format != "ascii" && format != "binary" && format != "appended")
    volume_fail(file, "DataArray.format", fmt::format("\"{}\" unknown (ascii, binary or appended)", format.substr(0, 80)));
  // Held beside the samples: the document's text (appended data are read from the file).
  check_budget(file, "WholeExtent", v, type, text.xml.size(), options);
  const std::size_t count = static_cast<std::size_t>(v.dims[0]) * v.dims[1] * v.dims[2];

  if (format == "ascii") {
    v.samples = ascii_array(file, type, array.child_value(), count);
    return v;
  }
  std::optional<Base64FileStream> stream;
  const ArrayBytes bytes = array_bytes(file, root, array, format, text, stream);
  const std::uint64_t held = count * scalar_bytes(type) + text.xml.size();
  const std::uint64_t table_budget = max_bytes > held ? max_bytes - held : 0;
  v.samples = read_samples(type, count, e.big_endian, [&](unsigned char* out, std::size_t need) {
    binary_array(file, e, bytes, out, need, table_budget);
  });
  return v;
}

}  // namespace vrv
