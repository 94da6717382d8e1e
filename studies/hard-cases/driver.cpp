// Study kind "hard_cases" (studies/hard-cases/hard_cases.h) as a study driver: reads the file,
// runs the cases, writes cases.{csv,md,tex} and one check per (case, method).
#include <cmath>
#include <string>
#include <utility>

#include <fmt/format.h>

#include "studies/engine/checkpoint.h"
#include "studies/engine/study_driver.h"
#include "studies/hard-cases/hard_cases.h"

namespace vrv {

std::vector<StudyCheck> hard_case_checks(const HardCasesResult& result) {
  std::vector<StudyCheck> checks;
  // A row with a bound (the reference's own estimate, a stated max_error whose derivation is next
  // to it in the study file, or the rule's a-priori bound) checks the error against it; a row
  // without one is a finiteness check only, says so and is labelled `finite`.
  for (const CaseRow& r : result.cases) {
    const bool bounded = std::isfinite(r.bound);
    std::string detail;
    if (!r.finite) {
      detail = "value not finite";
    } else if (r.bound_source == BoundSource::reference) {
      detail = "error against the truth within the reference's own estimate (+ the truth's), estimate within its tol";
    } else if (r.bound_source == BoundSource::stated) {
      detail = "error against the reference within the stated max_error (derived in the file)";
    } else if (r.bound_source == BoundSource::a_priori) {
      detail = "error against the truth within the rule's a-priori bound (+ the truth's estimate; "
               "lib/discrete_error_bound.h)";
    } else {
      detail = fmt::format("finiteness only: no error bound stated or derived (error {:.3g}, recorded in cases.csv)",
                           r.error);
    }
    checks.push_back({fmt::format("{} / {}{}", r.case_name, r.method, bounded || !r.finite ? "" : ": finite"),
                      r.error, r.bound, r.pass, std::move(detail),
                      bounded || !r.finite ? CheckKind::derived : CheckKind::finite});
  }
  return checks;
}

namespace {

StudyPlan parse_hard_cases(const StudyInput& in) {
  HardCasesStudy study = read_hard_cases_study(in);
  StudyJob job = [study](const StudyRun& run) {
    const HardCasesResult result = run_hard_cases(study, run.audit, run.progress, checkpoint_function(run.checkpoints));
    write_hard_case_tables(run.dir, study, result);
    StudyOutcome out;
    out.checks = hard_case_checks(result);
    out.parameters = hard_cases_parameters(study, run.quick, 0);
    out.parameters["cases_summary"] = case_summary_json(result);
    out.summary = fmt::format("{} cases", result.case_summary.size());
    return out;
  };
  return {std::move(job), [study](bool) { return hard_cases_work(study); }};
}

const RegisterStudyKind kHardCases{"hard_cases", parse_hard_cases};

}  // namespace
}  // namespace vrv
