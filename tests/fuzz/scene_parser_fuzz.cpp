// Fuzz target: the scene-file parser.  Any input parses or gives one short SceneFileError line.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "lib/scene_file.h"
#include "tests/fuzz/fuzz_limits.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  if (!vrv::fuzz::worth_running(text)) return -1;  // not added to the corpus
  try {
    vrv::parse_scene(text, "fuzz.toml");
  } catch (const vrv::SceneFileError& e) {
    const std::string msg = e.what();
    if (msg.find('\n') != std::string::npos || msg.size() > 2000) std::abort();  // one short line
  }
  return 0;
}
