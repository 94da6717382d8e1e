// Fuzz target: the bounds file of `vrv verify --bounds` and `vrv gate` (lib/bounds_file).  Any
// input gives its cases, each named and with at least one step or image, or one short
// BoundsFileError line naming the file.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "lib/bounds_file.h"
#include "tests/fuzz/fuzz_limits.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  if (!vrv::fuzz::worth_running(text)) return -1;  // not added to the corpus
  try {
    const vrv::BoundsFile file = vrv::parse_bounds(text, "fuzz.toml");
    for (const vrv::GateCase& c : file.cases)
      if (c.name.empty() || (c.steps.empty() && c.images.empty() && c.study.empty())) std::abort();
  } catch (const vrv::BoundsFileError& e) {
    const std::string msg = e.what();
    if (msg.rfind("fuzz.toml:", 0) != 0 || msg.find('\n') != std::string::npos || msg.size() > 2000)
      std::abort();
  }
  return 0;
}
