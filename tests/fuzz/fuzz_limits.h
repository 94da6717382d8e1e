#pragma once
// What the fuzz harnesses skip: valid inputs whose cost is legitimate (a large grid takes its
// memory; a fine step takes its time).  Those are the work and memory budgets' business (tested
// elsewhere); a fuzzer that stopped at each would find nothing else.  Everything else a harness
// is given must parse or be refused with the reader's own error, never crash, hang or leak.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string_view>

#include <toml++/toml.h>

#include "lib/io/image_structure.h"
#include "lib/scene_file.h"

namespace vrv::fuzz {

inline constexpr std::int64_t kMaxGridNodes = std::int64_t{1} << 18;  // 64^3
inline constexpr std::size_t kMaxInputBytes = std::size_t{1} << 16;

// Every `resolution = [a, b, c]` array anywhere in the document (the scene file's [field] and a
// study's [scene.field] or [render]), read as the memory estimates read it (node_counts_at), holds
// at most kMaxGridNodes nodes.
inline bool grids_are_small(const toml::node& n) {
  if (const auto* t = n.as_table()) {
    const auto nodes = vrv::node_counts_at(*t, "resolution");
    if (nodes && vrv::grid_bytes(*nodes) > static_cast<double>(kMaxGridNodes) * sizeof(double)) return false;
    for (const auto& [key, value] : *t)
      if (!grids_are_small(value)) return false;
  } else if (const auto* a = n.as_array()) {
    for (const auto& e : *a)
      if (!grids_are_small(e)) return false;
  }
  return true;
}

// Images claiming more pixels than this are skipped by the image harness: OpenImageIO allocates
// what the header claims before it finds the data short (a damaged EXR claiming 10^8 pixels took
// minutes of a shard), which is the cost of a large image, as a large grid's is its memory.
inline constexpr std::int64_t kMaxImagePixels = std::int64_t{1} << 20;

// The pixels an EXR's dataWindow or a PNG's IHDR claims (-1: neither, or no such header found), in
// double: two sides of up to 2^32 overflow a 64-bit integer.
inline double claimed_image_pixels(std::string_view b) {
  const auto u32 = [&](std::size_t at, bool big) {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i)
      v |= std::uint32_t{static_cast<unsigned char>(b[at + (big ? 3 - i : i)])} << (8 * i);
    return v;
  };
  if (b.size() >= 24 && b.substr(0, 8) == std::string_view("\x89PNG\r\n\x1a\n", 8) && b.substr(12, 4) == "IHDR")
    return static_cast<double>(u32(16, true)) * static_cast<double>(u32(20, true));
  // EXR: the largest dataWindow of its parts (16 bytes whatever it declares, as OpenEXR reads a box2i).
  double pixels = -1;
  vrv::walk_exr_attributes(b, b.size(), [&](const vrv::ExrAttribute& a) {
    if (a.name != "dataWindow" || a.value + 16 > b.size()) return true;
    // A side of the box (max - min + 1; at most 2^32, none below 0: an inverted box holds nothing).
    const auto side = [&](std::size_t lo, std::size_t hi) {
      const auto i32 = [&](std::size_t k) { return static_cast<double>(static_cast<std::int32_t>(u32(a.value + 4 * k, false))); };
      return std::max(0.0, i32(hi) - i32(lo) + 1);
    };
    pixels = std::max(pixels, side(0, 2) * side(1, 3));
    return true;
  });
  return pixels;
}

// False for inputs the harness skips: too long, or (when it is TOML at all) a large grid.
inline bool worth_running(std::string_view text) {
  if (text.size() > kMaxInputBytes) return false;
  if (toml_nesting_problem(text)) return true;  // the readers refuse it before toml++ sees it
  try {
    return grids_are_small(toml::parse(text));
  } catch (const toml::parse_error&) {
    return true;  // the readers report it
  }
}

// Where harnesses that go through files put them: /dev/shm when there is one, since vrv writes
// files atomically with fsync (a checkpoint, a cache entry), which on a disk made 20,000 inputs
// take minutes of waiting.
inline std::filesystem::path scratch_root() {
  std::error_code ec;
  return std::filesystem::is_directory("/dev/shm", ec) ? std::filesystem::path("/dev/shm")
                                                         : std::filesystem::temp_directory_path();
}

}  // namespace vrv::fuzz
