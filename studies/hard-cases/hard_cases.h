#pragma once
// Study kind "hard_cases": the stability cases (extreme optical depth, near-zero extinction,
// grazing and corner rays, N = 1024, float at tiny steps, steps and peaks in the transfer
// function), each a scene, a ray and a list of methods whose value, error, bound and finiteness
// are recorded and gated.  See studies/hard-cases/hard-cases.toml and docs/studies.md.
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "lib/study_file.h"
#include "lib/scene.h"
#include "studies/engine/checkpoint.h"
#include "studies/engine/reference_audit.h"
#include "studies/engine/study_driver.h"

namespace vrv {

// One method run on a hard case: see StudyMethodSpec (lib/study_file.h).
using HardCaseMethod = StudyMethodSpec;

struct HardCase {
  std::string name;
  std::string description;
  std::string scene_toml;  // the case's [scene] table, as TOML text
  Scene scene;
  Vec3 origin{0, 0, 0}, direction{1, 0, 0};
  std::vector<HardCaseMethod> methods;
};

struct HardCasesStudy {
  std::string name;         // `name` key, else the file's stem
  std::string source;       // the file (or source name) it came from
  std::string description;
  double reference_tol = 1e-13;  // the tolerance of the "truth" each error is against
  std::vector<HardCase> cases;
};

// Where a row's bound comes from.
enum class BoundSource { reference, stated, a_priori, none };

// One row of a hard-cases study: one method on one case.
struct CaseRow {
  std::string case_name, method;
  bool reference = false;
  double value = 0;
  double error = 0;   // |value - reference at reference_tol|
  // reference: its error_estimate; discrete: the stated max_error, else the a-priori bound
  // (lib/discrete_error_bound.h) where one is derived, else NaN.
  double bound = 0;
  BoundSource bound_source = BoundSource::none;
  bool finite = false;
  long samples = 0;   // discrete: field samples; reference: field evaluations
  bool pass = false;
};

struct CaseSummary {
  std::string name;
  double truth = 0, truth_estimate = 0;  // the reference at reference_tol and its error_estimate
  long nan_count = 0;                    // non-finite values among the case's rows (and truth)
  bool pass = true;
};

struct HardCasesResult {
  std::vector<CaseRow> cases;            // case-major, methods in file order
  std::vector<CaseSummary> case_summary;  // one per case
  long rays = 0;
  bool pass = true;
};

// Throws StudyFileError for any problem (unknown method or key; missing key; a bad [scene]).
HardCasesStudy read_hard_cases_study(const StudyInput& in);
HardCasesStudy parse_hard_cases_study(std::string_view toml_text, std::string_view source_name,
                                      std::string_view default_name);
HardCasesStudy load_hard_cases_study(const std::filesystem::path& path);

// Per case the truth (reference at reference_tol), then every (case, method) in parallel, each
// into its own slot.  quick runs the same cases (they are cheap).  A case passes when every row
// is finite and, for reference rows, error <= error_estimate + truth's estimate and
// error_estimate <= tol, for discrete rows with max_error, error <= max_error, and for discrete
// rows with an a-priori bound, error <= bound + truth's estimate.
// checkpoint (studies/engine/checkpoint.h): each case's truth and each (case, method) row; the
// truths are counted in `audit`.
HardCasesResult run_hard_cases(const HardCasesStudy& study, ReferenceAudit& audit, bool progress,
                               const StudyCheckpoint& checkpoint = {});

// Field evaluations of the run (the same for --quick), on each case's own ray.
StudyWork hard_cases_work(const HardCasesStudy& study);

struct HardCaseFiles {
  std::string cases_csv, cases_md, cases_tex;
};
HardCaseFiles hard_case_tables(const HardCasesStudy& study, const HardCasesResult& result);

// The full parameters recorded in meta.json.
nlohmann::json hard_cases_parameters(const HardCasesStudy& study, bool quick, int threads);

// Writes cases.csv, cases.md and cases.tex into `dir`, each atomically; and the per-case summary
// as meta.json has it.
void write_hard_case_tables(const std::filesystem::path& dir, const HardCasesStudy& study,
                            const HardCasesResult& result);
nlohmann::json case_summary_json(const HardCasesResult& result);

// One check per (case, method): against the reference's own estimate, the stated max_error or the
// a-priori bound (kind derived), or, with none of them, that the value is finite (kind finite).
std::vector<StudyCheck> hard_case_checks(const HardCasesResult& result);

}  // namespace vrv
