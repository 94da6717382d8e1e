#include "lib/verify/reference_cache.h"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>

#include <fmt/format.h>

#include "lib/io/atomic_file.h"
#include "lib/util/checksum.h"

namespace vrv {
namespace {

namespace fs = std::filesystem;

std::string camera_text(const Camera& c) {
  return fmt::format("camera {} eye {:.17g} {:.17g} {:.17g} target {:.17g} {:.17g} {:.17g} up {:.17g} "
                     "{:.17g} {:.17g} fov {:.17g} extent {:.17g} angle {:.17g} size {} x {}",
                     to_string(c.projection), c.eye[0], c.eye[1], c.eye[2], c.target[0], c.target[1],
                     c.target[2], c.up[0], c.up[1], c.up[2], c.fov_degrees, c.extent, c.angle_degrees,
                     c.width, c.height);
}

// Version 2 ends with the CRC-64 of everything before it (lib/util/checksum.h): a file whose
// values were changed (the verdict flipped before) or cut is recomputed, never used.
constexpr std::string_view kCacheMagic = "vrv reference cache 2\n";

// The file's bytes when it is a whole cache entry for `key` with w x h pixels.
std::optional<std::string> cache_entry(const fs::path& file, const std::string& key, int w, int h) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream text;
  text << in.rdbuf();
  const std::string bytes = text.str();
  const std::size_t key_end = kCacheMagic.size() + sizeof(std::uint64_t) + key.size();
  const std::size_t crc_at = key_end + 3 * sizeof(double) * static_cast<std::size_t>(w) * h;
  const auto recompute = [&](std::string_view why) {
    std::cerr << fmt::format("vrv: the reference cache {} {}; recomputing it\n", file.string(), why);
    return std::nullopt;
  };
  if (!bytes.starts_with(kCacheMagic) || bytes.size() != crc_at + sizeof(std::uint64_t) ||
      bytes.compare(key_end - key.size(), key.size(), key) != 0)
    return recompute("is not this reference's (another vrv version, key or image size)");
  std::uint64_t crc = 0;
  std::memcpy(&crc, bytes.data() + crc_at, sizeof crc);
  if (crc != crc64(std::string_view(bytes).substr(0, crc_at))) return recompute("fails its checksum (changed or damaged)");
  return bytes;
}

}  // namespace

std::string reference_cache_key(const std::string& scene_text, const Camera& camera, double tol) {
  return fmt::format("vrv reference\nscene\n{}\n{}\ntol {:.17g}\n", scene_text, camera_text(camera), tol);
}

std::string reference_cache_name(const std::string& key) { return fmt::format("reference-{}.bin", crc64_hex(key)); }

std::optional<ReferenceImage> read_reference_cache(const fs::path& file, const std::string& key, int w, int h) {
  const std::optional<std::string> bytes = cache_entry(file, key, w, h);
  if (!bytes) return std::nullopt;
  ReferenceImage r(w, h);
  const std::size_t n = r.pixel_count();
  const char* at = bytes->data() + kCacheMagic.size() + sizeof(std::uint64_t) + key.size();
  for (std::vector<double>* plane : {&r.pixels, &r.error_estimate, &r.optical_depth}) {
    std::memcpy(plane->data(), at, n * sizeof(double));
    at += n * sizeof(double);
  }
  r.from_cache = true;
  r.cache_file = file.string();
  return r;
}

void write_reference_cache(const fs::path& file, const std::string& key, const ReferenceImage& r) {
  std::string bytes(kCacheMagic);
  const std::uint64_t key_size = key.size();
  bytes.append(reinterpret_cast<const char*>(&key_size), sizeof key_size);
  bytes += key;
  for (const std::vector<double>* plane : {&r.pixels, &r.error_estimate, &r.optical_depth})
    bytes.append(reinterpret_cast<const char*>(plane->data()), plane->size() * sizeof(double));
  const std::uint64_t crc = crc64(bytes);
  bytes.append(reinterpret_cast<const char*>(&crc), sizeof crc);
  write_file_atomically(file, bytes);
}

}  // namespace vrv
