#pragma once
// Image files whose headers claim more bytes than the file holds are refused before OpenImageIO
// reads them: libpng allocates and zeroes a PNG chunk's claimed length (up to 2^31 - 1 bytes), and
// OpenEXR an attribute's, before either finds the file ends.  The image fuzzer made both: a
// 632-byte PNG whose tEXt chunk claims 1.6e9 bytes (35 s under the sanitizers, 4.5 s in Release)
// and an 870-byte EXR whose vrv:step attribute claims 1.8e9
// (tests/fuzz/corpus/image_reader/chunk_length_past_end.png, attribute_length_past_end.exr).
// Only the lengths are walked (PNG chunk headers; EXR header attributes); contents and CRCs are
// the libraries' business: this is what they do not bound cheaply themselves.
#include <filesystem>
#include <string>
#include <string_view>

namespace vrv {

// "" for bytes that are neither PNG nor OpenEXR, or whose lengths fit; else the reason, e.g.
// "PNG chunk 'tEXt' at byte 292 claims 1627389980 bytes, 327 are left (damaged or truncated)".
std::string image_structure_problem(std::string_view bytes);

// The same for a file: a PNG's chunk headers are read one by one, an EXR's header (at most its
// first 16 MiB: attributes are small) whole; "" when it cannot be read (the reader says why).
std::string image_file_structure_problem(const std::filesystem::path& file);

}  // namespace vrv
