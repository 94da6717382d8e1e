#pragma once
// Rays as JSON lines (`vrv ray --rays FILE|-`): one object per line,
//   {"origin": [x, y, z], "direction": [x, y, z], "id": <any JSON value, optional>}
// blank lines skipped.  The whole input is read and checked before any ray is cast, so a bad
// line never leaves half the results printed.
#include <istream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "lib/geometry.h"

namespace vrv {

struct RayLine {
  long line = 0;       // 1-based line number in the input
  Ray ray;             // normalised direction
  nlohmann::json id;   // the line's "id", passed through; null when absent
};

// Every ray of `in`.  Throws std::invalid_argument "<name>:<line>: <reason>" for the first bad
// line: invalid JSON (with the column, and why: NaN/Infinity, a number beyond a double, a
// truncated object), not an object, an unknown key, a missing or malformed origin/direction, a
// zero direction.
std::vector<RayLine> read_rays(std::istream& in, const std::string& name);

}  // namespace vrv
