#pragma once
// A study kind is a driver: it reads its own keys from the study file (StudyReader: every problem
// one line, exit 2), then runs and writes its own tables, images and plots.json into the study's
// directory.  `vrv study` (studies/engine/study_runner.h) does the rest the same way for every kind:
// finds the file, makes the directory, times the run, writes checks.{csv,md,tex} and meta.json
// (run metadata, the full study file, the checks), draws the plots, and exits 1 if a check failed.
//
// A driver registers itself from its own .cpp file:
//   const RegisterStudyKind kSampling{"sampling", parse_sampling_study};
// where parse_sampling_study(const StudyInput&) validates the file and returns the job to run
// with an estimate of its work (study_work.h), which `vrv study` checks before running it.  A
// kind that builds grids of its own (beyond its scenes' [field] tables) declares them too, for the
// memory estimate made before the file is read (memory_budget.h):
//   const RegisterStudyKind kShading{"shading", parse_shading, shading_grids};
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include "lib/study_file.h"
#include "lib/order_estimate.h"
#include "studies/engine/memory_budget.h"
#include "studies/engine/study_work.h"

namespace vrv {

// The whole study file, parsed; `kind`, `name` and `description` are read by the framework, every
// other top-level key is the driver's (it must reject keys it does not know).
struct StudyInput {
  const toml::table& doc;
  const StudyReader& reader;
  std::string name;
};

// A kind's file read outside `vrv study` (its tests, a driver's own loader): parsed, read by `read`
// as the runner would, and its scenes required grey (only the runner splits an RGB study into one
// study per channel).  Throws StudyFileError.
template <class Read>
auto read_grey_study(std::string_view text, std::string_view source_name, std::string_view default_name,
                     const Read& read) {
  const StudyReader reader(source_name);
  const toml::table doc = parse_study_toml(text, source_name);
  auto study = read(StudyInput{doc, reader, std::string(default_name)});
  reader.require_grey_scenes();
  return study;
}

class Checkpoints;     // studies/engine/checkpoint.h
class ReferenceAudit;  // studies/engine/reference_audit.h

struct StudyRun {
  std::filesystem::path dir;  // exists; write every file with write_file_atomically
  bool quick = false;         // the --quick variant (tests, CI): under a minute on two cores
  bool progress = false;      // a progress bar on stderr is welcome
  // Where a driver stores each finished configuration (checkpointed(), for --resume); may be null.
  Checkpoints* checkpoints = nullptr;
  // Where the run's truths are counted (audited_reference): the runner's check of them.
  ReferenceAudit& audit;
};

// Where a check's bound comes from (docs/studies.md, "Four kinds of check"):
//   derived     from theory or from the fit's own spread (a regression in the code can trip it);
//   regression  a measured maximum rounded up: the study file says so next to the number, with
//               the measurement and the command that made it;
//   identity    true by construction, kept as a sanity check (it cannot show a finding);
//   finite      no error bound is stated: only that the value is finite (the error is recorded).
// `unlabelled` is refused by `vrv study`: every check must say which it is.
enum class CheckKind { unlabelled, derived, regression, identity, finite };
std::string_view check_kind_name(CheckKind kind);

// One invariant the study checked: `value` compared with `bound` (pass is decided by the driver,
// e.g. value <= bound, or |value - expected| <= tolerance); `detail` says what was compared.
struct StudyCheck {
  std::string name;
  double value = 0;
  double bound = 0;
  bool pass = false;
  std::string detail;
  CheckKind kind = CheckKind::unlabelled;
};

struct StudyOutcome {
  std::vector<StudyCheck> checks;
  nlohmann::json parameters = nlohmann::json::object();  // what the run used (beyond the file)
  std::string summary;  // one line for stderr, e.g. "5 methods, all orders within 0.25"
};

using StudyJob = std::function<StudyOutcome(const StudyRun&)>;
// The job's field evaluations, for the full run or the --quick one (`quick`), estimated without
// casting a ray: each part (a configuration, or a group of them) its rays times the evaluations
// on the longest of them (lib/work_estimate.h).
using StudyWorkEstimate = std::function<StudyWork(bool quick)>;
struct StudyPlan {
  StudyJob job;
  StudyWorkEstimate work;
};
using StudyParse = StudyPlan (*)(const StudyInput&);  // throws StudyFileError

struct RegisterStudyKind {
  RegisterStudyKind(std::string kind, StudyParse parse, StudyGrids grids = nullptr);
};

// nullptr when no driver has that kind.
StudyParse find_study_kind(std::string_view kind);
// The kind's own grids (nullptr: none, or no such kind).
StudyGrids find_study_grids(std::string_view kind);
std::vector<std::string> study_kinds();  // sorted

// An observed order against the expected one, the tolerance derived from the fit's spread
// (lib/order_estimate.h): value |observed - expected|, bound the tolerance, kind derived.
StudyCheck order_check(std::string name, const OrderEstimate& fit, double expected, const OrderTolerance& tolerance);

// The drivers' common output: tables from the checks.
struct CheckTables {
  std::string csv, md, tex;
};
CheckTables check_tables(const std::string& study_name, const std::vector<StudyCheck>& checks);

// Keys every study file may have at the top level; drivers add their own to this list.
inline constexpr std::string_view kStudyCommonKeys[] = {"kind", "name", "description"};

}  // namespace vrv
