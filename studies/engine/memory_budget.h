#pragma once
// A study's memory, estimated from its file before anything is built: a dozen 512^3 grid cases
// in a 7 KB file ask for more memory than most machines have, and each grid is built while the
// file is read.  The estimate counts every grid the file describes as held at once, 8 bytes a
// node: each [field] table's grid as its kind tells (lib/scene_file.h field_grid_nodes), and the
// grids the study kind builds of its own, as the kind declares them (StudyGrids).  An upper bound
// on what the grids need, which dominate a study's memory.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "lib/scene_file.h"

namespace vrv {

// The grids a study kind builds of its own, beyond its scenes' [field] tables, as node counts
// from its file before the driver reads it (studies/engine/study_driver.h RegisterStudyKind).
// Lenient: what it cannot read, the driver's reader reports.
using StudyGrids = std::vector<NodeCounts> (*)(const toml::table& doc);

// For a StudyGrids: the n^3 grid of the largest whole number `key` holds (a number, or a list of
// them built one at a time), or nothing.
std::optional<NodeCounts> largest_cube(const toml::table& t, std::string_view key);

struct StudyMemory {
  double bytes = 0;
  long grids = 0;
  NodeCounts largest{0, 0, 0};  // the largest grid's resolution
};

StudyMemory estimate_study_memory(const toml::table& doc, StudyGrids own = nullptr);

// The default limit: three quarters of this machine's physical memory.
double default_memory_limit();

// "about 12.0 GiB (12 grids, the largest 512x512x512)".
std::string describe(const StudyMemory& m);
std::string gibibytes(double bytes);  // "12.0 GiB"

}  // namespace vrv
