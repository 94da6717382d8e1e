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

// What a counting pass over a rays input saw: its non-blank lines (the rays it would give) and
// the bytes read to find them.
struct RayLineCount {
  long lines = 0;
  long bytes = 0;
};

// The non-blank lines of `in`, found without parsing or storing them, the count stopping once it
// passes `stop_after` (so a file far above a work limit is refused after reading only what the
// limit allows: 10 M rays were refused after 219 s and 1.2 GB of parsing).
RayLineCount count_ray_lines(std::istream& in, long stop_after);

}  // namespace vrv
