#pragma once
// Scene files: the volume box, field, transfer function and background as TOML.
//
// Strict on purpose: unknown keys, wrong types, non-finite numbers and out-of-range values
// are errors, never silently replaced by defaults; only documented optional keys default.
#include <filesystem>
#include <stdexcept>
#include <string_view>

#include "lib/scene.h"

namespace vrv {

// One line: "<file>: <key>: <reason>", e.g.
// "scene.toml: transfer.extinction[2]: negative extinction -0.5".
class SceneFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// source_name only labels error messages.  Throws SceneFileError.
Scene parse_scene(std::string_view toml_text, std::string_view source_name);
// Reads and parses the file; an unreadable file is a SceneFileError naming it.
Scene load_scene(const std::filesystem::path& path);

// The built-in Marschner-Lobb scene as TOML text, and parsed.
std::string_view default_scene_toml();
Scene default_scene();

}  // namespace vrv
