#pragma once
// Image files whose headers claim more bytes than the file holds are refused before OpenImageIO
// reads them: libpng allocates and zeroes a PNG chunk's claimed length (up to 2^31 - 1 bytes), and
// OpenEXR an attribute's, before either finds the file ends.  The image fuzzer made both: a
// 632-byte PNG whose tEXt chunk claims 1.6e9 bytes (35 s under the sanitizers, 4.5 s in Release)
// and an 870-byte EXR whose vrv:step attribute claims 1.8e9
// (tests/fuzz/corpus/image_reader/chunk_length_past_end.png, attribute_length_past_end.exr).
// A third: a 447-byte EXR whose channel list declares 19 bytes and takes 20.  OpenEXR reads a
// channel list to its end and fixed-size types by their own size, not by the declared size, so it
// read on one byte out of step, took the text "inte" for a string's size and allocated 1.7 GB
// (tests/fuzz/corpus/image_reader/channel_list_size_wrong.exr).  The walk therefore steps as
// OpenEXR does.  Only the lengths are walked (PNG chunk headers; EXR header attributes); contents
// and CRCs are the libraries' business: this is what they do not bound cheaply themselves.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

namespace vrv {

// "" for bytes that are neither PNG nor OpenEXR, or whose lengths fit; else the reason, e.g.
// "PNG chunk 'tEXt' at byte 292 claims 1627389980 bytes, 327 are left (damaged or truncated)".
std::string image_structure_problem(std::string_view bytes);

// The same for a file: a PNG's chunk headers are read one by one, an EXR's header (at most its
// first 16 MiB: attributes are small) whole; "" when it cannot be read (the reader says why).
std::string image_file_structure_problem(const std::filesystem::path& file);

// The bytes OpenEXR 3's header reader takes for an attribute of `type` whose value starts at
// `value` in `bytes`, declared `declared` bytes long: a channel list's entries and end (nullopt
// when they do not end within `bytes`), a fixed-size type's own size, a float vector's whole
// floats, an ID manifest's declared size + 4 (OpenEXR 3.1.5 reads that much), else the declared size.
std::optional<std::uint64_t> exr_value_extent(std::string_view type, std::string_view bytes, std::uint64_t value,
                                              std::uint64_t declared);

// One attribute of an EXR header: its name and type, where it starts, where its value starts and
// the length it declares (offsets into the bytes walked).
struct ExrAttribute {
  std::string_view name, type;
  std::uint64_t at = 0, value = 0, length = 0;
};
// Visits the header attributes of the EXR `bytes` (the file's first part: `size` is the whole
// file's) in order, stepping from one to the next as OpenEXR does (exr_value_extent; a multipart
// file's headers in turn).  Stops where `visit` returns false, after visiting an attribute whose
// declared length runs past `size`, or where the headers end or the bytes are cut off.  What is
// not EXR has no attributes.
void walk_exr_attributes(std::string_view bytes, std::uint64_t size,
                         const std::function<bool(const ExrAttribute&)>& visit);

}  // namespace vrv
