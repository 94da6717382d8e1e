// Fuzz target: the rays file of `vrv ray --rays` (lib/rays_file).  Any input gives its rays,
// each with a finite origin and a unit direction, or one std::invalid_argument line naming the
// input and the line.  No size cut-off: the reader bounds its lines and their nesting itself, and
// a cut-off hid the 70,000-deep id that overflowed the stack (issue 22).
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <string>

#include "lib/rays_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    for (const vrv::RayLine& r : vrv::read_rays(in, "fuzz.jsonl")) {
      if (!r.ray.origin.allFinite() || !r.ray.direction.allFinite()) std::abort();
      if (std::abs(r.ray.direction.norm() - 1) > 1e-12) std::abort();
    }
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    if (msg.rfind("fuzz.jsonl:", 0) != 0 || msg.find('\n') != std::string::npos || msg.size() > 2000)
      std::abort();
  }
  return 0;
}
