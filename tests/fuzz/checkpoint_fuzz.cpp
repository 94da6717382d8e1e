// Fuzz target: a study checkpoint as `vrv study --resume` reads it (studies/engine/checkpoint.h)
// and the reference audit's snapshot beside it (reference_audit.h).  A checkpoint file with any
// bytes gives its values only when its end line's count and CRC-64 match them, else one
// StudyResumeError line naming the file; a snapshot parses or is refused (nullopt), never a crash.
// Issue 22: a checkpoint holding only `end` crashed, one with values removed was used.
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "studies/engine/checkpoint.h"
#include "studies/engine/reference_audit.h"

#include "tests/fuzz/fuzz_limits.h"

namespace fs = std::filesystem;

namespace {

const fs::path& checkpoint_dir() {
  static const fs::path dir = [] {
    const fs::path d = vrv::fuzz::scratch_root() / ("vrv-fuzz-checkpoint-" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
  }();
  return dir;
}

void check_one_line(const std::string& msg, const std::string& file) {
  if (msg.rfind(file + ": ", 0) != 0 || msg.find('\n') != std::string::npos || msg.size() > 2000) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const fs::path file = checkpoint_dir() / "ray_0.txt";
  std::ofstream(file, std::ios::binary | std::ios::trunc).write(bytes.data(), static_cast<std::streamsize>(size));
  static vrv::Checkpoints checkpoints(checkpoint_dir(), "fuzz", true);  // reads the file on each get()
  const auto never = []() -> std::vector<double> { std::abort(); };  // the file is there: read, or refused
  for (const std::optional<std::size_t> expected : {std::optional<std::size_t>(), std::optional<std::size_t>(3)}) {
    try {
      const std::vector<double> values = checkpoints.get("ray_0", never, expected);
      if (expected && values.size() != *expected) std::abort();
    } catch (const vrv::StudyResumeError& e) {
      check_one_line(e.what(), file.string());
    }
  }
  if (const auto counts = vrv::parse_reference_audit_snapshot(bytes)) {
    // What parses writes back to the same counts (the snapshot is exact).
    const auto again = vrv::parse_reference_audit_snapshot(vrv::reference_audit_snapshot(*counts));
    if (!again || again->rays != counts->rays || again->missed != counts->missed) std::abort();
  }
  return 0;
}
