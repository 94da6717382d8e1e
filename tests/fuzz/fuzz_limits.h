#pragma once
// What the fuzz harnesses skip: valid inputs whose cost is legitimate (a large grid takes its
// memory; a fine step takes its time).  Those are the work and memory budgets' business (tested
// elsewhere); a fuzzer that stopped at each would find nothing else.  Everything else a harness
// is given must parse or be refused with the reader's own error, never crash, hang or leak.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string_view>

#include <toml++/toml.h>

#include "lib/scene_file.h"

namespace vrv::fuzz {

inline constexpr std::int64_t kMaxGridNodes = std::int64_t{1} << 18;  // 64^3
inline constexpr std::size_t kMaxInputBytes = std::size_t{1} << 16;

// The product of every `resolution = [a, b, c]` array anywhere in the document (the scene
// file's [field] and a study's [scene.field]) stays under kMaxGridNodes.
inline bool grids_are_small(const toml::node& n) {
  if (const auto* t = n.as_table()) {
    for (const auto& [key, value] : *t) {
      if (key.str() == "resolution" && value.is_array()) {
        std::int64_t nodes = 1;
        for (const auto& e : *value.as_array()) {
          const auto* i = e.as_integer();
          if (!i) continue;  // the reader refuses it
          if (i->get() <= 0) return true;
          if (i->get() > kMaxGridNodes || (nodes *= i->get()) > kMaxGridNodes) return false;
        }
      }
      if (!grids_are_small(value)) return false;
    }
  } else if (const auto* a = n.as_array()) {
    for (const auto& e : *a)
      if (!grids_are_small(e)) return false;
  }
  return true;
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
