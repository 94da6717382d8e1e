#pragma once
// Scene files: the volume box, field, transfer function and background as TOML.
//
// Strict on purpose: unknown keys, wrong types, non-finite numbers and out-of-range values
// are errors, never silently replaced by defaults; only documented optional keys default.
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <stdexcept>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

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
// The same, with a kind = "volume" field's file refused (one line naming it and --max-memory)
// when its samples, with what is held beside them while read and placed (a reader's buffer, the
// bits that reorder permuted axes), would take more than max_volume_bytes, checked from the
// file's header before its data are read (the commands' --max-memory).
Scene parse_scene(std::string_view toml_text, std::string_view source_name, double max_volume_bytes);
Scene load_scene(const std::filesystem::path& path, double max_volume_bytes);
// The file's text as load_scene reads it (its checks and errors), not parsed.
std::string read_scene_text(const std::filesystem::path& path);

// The scene's TOML as toml++ prints it (`vrv scene --print`), once parse_scene has accepted it:
// the keys given, numbers to the digits that read back to the same doubles.  Throws SceneFileError
// (a volume file above max_volume_bytes refused from its header, as load_scene's).
std::string scene_toml(std::string_view toml_text, std::string_view source_name, double max_volume_bytes);

// What `vrv export` wrote, as a scene (studies/cli/export.cpp): `toml_text` with its analytic
// [field] made the source of a node-layout trilinear grid of `grid_nodes` when given, and its
// [transfer] replaced by opacity/colour points when given.
struct OpacityColourPoints {
  std::vector<ControlPoint> opacity;
  std::vector<std::vector<double>> color;  // [v, c] (grey) or [v, r, g, b] (RGB)
  double unit_length = 1;
};
std::string exported_scene_toml(std::string_view toml_text, std::string_view source_name,
                                const std::optional<std::array<int, 3>>& grid_nodes,
                                const std::optional<OpacityColourPoints>& transfer);

// toml++ recurses once per key nesting level, so a dotted key of tens of thousands of parts
// would overflow the stack: every TOML reader (scene and study files) calls this before parsing.
// "line L, column C: key nested too deeply (...)" when `text` has such a key, else nullopt.
std::optional<std::string> toml_nesting_problem(std::string_view text);

// A grid's node counts along x, y and z.
using NodeCounts = std::array<std::int64_t, 3>;
// What a grid of `nodes` holds at most: 8 bytes a node (a volume's narrower samples take less).
double grid_bytes(const NodeCounts& nodes);
// The node counts `t[key]` holds: three whole numbers, each at least 1, or nothing.  Lenient, for
// the estimates made before a file is read: what it cannot read, the file's reader reports.
std::optional<NodeCounts> node_counts_at(const toml::table& t, std::string_view key);

// The node counts of the grid a [field] table describes, as its kind tells from the table alone
// before anything is read (a grid's resolution); nothing for an analytic field, for a volume (only
// its header tells: its reader checks it against max_volume_bytes where a caller gives one, and
// against the grid node cap always), and for a table that is not a field.  Lenient: a malformed
// table's error is the reader's.
std::optional<NodeCounts> field_grid_nodes(const toml::table& field);

// The built-in Marschner-Lobb scene as TOML text, and parsed.
std::string_view default_scene_toml();
Scene default_scene();

}  // namespace vrv
