// Fuzz target: the study-file reader, with every study kind's driver (what `vrv study FILE` does
// before it runs anything).  Any input loads or gives one short StudyFileError line; the memory
// budget is part of what is fuzzed (a small limit here, so no input builds a large grid), and so is
// the work estimate of both variants, which `vrv study` checks before running.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "lib/study_file.h"
#include "studies/engine/study_loader.h"
#include "tests/fuzz/fuzz_limits.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  if (size > vrv::fuzz::kMaxInputBytes) return -1;
  try {
    const vrv::LoadedStudy study = vrv::load_study_text(text, "fuzz.toml", "fuzz", {.memory_limit = 64.0 * (1 << 20)});
    vrv::check_study_work(study, true, 1e10);
    vrv::check_study_work(study, false, 1e10);
  } catch (const vrv::StudyFileError& e) {
    const std::string msg = e.what();
    if (msg.find('\n') != std::string::npos || msg.size() > 2000) std::abort();
  }
  return 0;
}
