#pragma once
// The reference cache: one binary file per reference image, named by the CRC-64 of its key (the
// scene's text, the camera with its size, the tolerance), holding the whole key (compared on
// reading, so a collision cannot return another scene's reference) and ending with the CRC-64 of
// everything before it, so a changed, damaged or cut file is recomputed, never used.
#include <filesystem>
#include <optional>
#include <string>

#include "lib/camera.h"
#include "lib/verify/reference_image.h"

namespace vrv {

std::string reference_cache_key(const std::string& scene_text, const Camera& camera, double tol);
// "reference-<crc64 of key>.bin"
std::string reference_cache_name(const std::string& key);

// The entry in `file` when it is a whole one for `key` with w x h pixels.  A missing file is a
// plain miss; any other is said in one stderr line (the caller recomputes and rewrites it).
std::optional<ReferenceImage> read_reference_cache(const std::filesystem::path& file, const std::string& key,
                                                   int w, int h);
// Written atomically (lib/io/atomic_file.h); std::runtime_error when it cannot be.
void write_reference_cache(const std::filesystem::path& file, const std::string& key, const ReferenceImage& r);

}  // namespace vrv
