#pragma once
// A study's memory, estimated from its file before anything is built: a dozen 512^3 grid cases
// in a 7 KB file ask for more memory than most machines have, and each grid is built while the
// file is read.  The estimate counts every grid the file describes (any `resolution = [nx, ny, nz]`,
// and the largest cube of any `resolutions` list) as held at once, 8 bytes a node: an upper
// bound on what the grids need, which dominate a study's memory.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <toml++/toml.h>

namespace vrv {

struct StudyMemory {
  double bytes = 0;
  long grids = 0;
  std::array<std::int64_t, 3> largest{0, 0, 0};  // the largest grid's resolution
};

StudyMemory estimate_study_memory(const toml::table& doc);

// The default limit: three quarters of this machine's physical memory.
double default_memory_limit();

// "about 12.0 GiB (12 grids, the largest 512x512x512)".
std::string describe(const StudyMemory& m);
std::string gibibytes(double bytes);  // "12.0 GiB"

}  // namespace vrv
