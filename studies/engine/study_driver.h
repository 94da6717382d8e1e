#pragma once
// A study kind is a driver: it reads its own keys from the study file (StudyReader: every problem
// one line, exit 2), then runs and writes its own tables, images and plots.json into the study's
// directory.  `vrv study` (studies/engine/study_runner.h) does the rest the same way for every kind:
// finds the file, makes the directory, times the run, writes checks.{csv,md,tex} and meta.json
// (run metadata, the full study file, the checks), draws the plots, and exits 1 if a check failed.
//
// A driver registers itself from its own .cpp file:
//   const RegisterStudyKind kSampling{"sampling", parse_sampling_study};
// where parse_sampling_study(const StudyInput&) validates the file and returns the job to run.
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include "lib/io/study_file.h"

namespace vrv {

// The whole study file, parsed; `kind`, `name` and `description` are read by the framework, every
// other top-level key is the driver's (it must reject keys it does not know).
struct StudyInput {
  const toml::table& doc;
  const StudyReader& reader;
  std::string name;
};

struct StudyRun {
  std::filesystem::path dir;  // exists; write every file with write_file_atomically
  bool quick = false;         // the --quick variant (tests, CI): under a minute on two cores
  bool progress = false;      // a progress bar on stderr is welcome
};

// One invariant the study checked: `value` compared with `bound` (pass is decided by the driver,
// e.g. value <= bound, or |value - expected| <= tolerance); `detail` says what was compared.
struct StudyCheck {
  std::string name;
  double value = 0;
  double bound = 0;
  bool pass = false;
  std::string detail;
};

struct StudyOutcome {
  std::vector<StudyCheck> checks;
  nlohmann::json parameters = nlohmann::json::object();  // what the run used (beyond the file)
  std::string summary;  // one line for stderr, e.g. "5 methods, all orders within 0.25"
};

using StudyJob = std::function<StudyOutcome(const StudyRun&)>;
using StudyParse = StudyJob (*)(const StudyInput&);  // throws StudyFileError

struct RegisterStudyKind {
  RegisterStudyKind(std::string kind, StudyParse parse);
};

// nullptr when no driver has that kind.
StudyParse find_study_kind(std::string_view kind);
std::vector<std::string> study_kinds();  // sorted

// The drivers' common output: tables from the checks.
struct CheckTables {
  std::string csv, md, tex;
};
CheckTables check_tables(const std::string& study_name, const std::vector<StudyCheck>& checks);

// Keys every study file may have at the top level; drivers add their own to this list.
inline constexpr std::string_view kStudyCommonKeys[] = {"kind", "name", "description"};

}  // namespace vrv
