// Study kind "hard_cases" (studies/hard-cases/hard_cases.h) as a study driver: reads the file,
// runs the cases, writes cases.{csv,md,tex} and one check per (case, method).
#include <fmt/format.h>

#include "studies/engine/study_driver.h"
#include "studies/hard-cases/hard_cases.h"

namespace vrv {
namespace {

std::vector<StudyCheck> checks_of(const HardCasesResult& result) {
  std::vector<StudyCheck> checks;
  for (const CaseRow& r : result.cases)
    checks.push_back({fmt::format("{} / {}", r.case_name, r.method), r.error, r.bound, r.pass,
                      r.finite ? "error against the reference within the bound" : "value not finite"});
  return checks;
}

StudyJob parse_hard_cases(const StudyInput& in) {
  HardCasesStudy study = read_hard_cases_study(in);
  return [study](const StudyRun& run) {
    const HardCasesResult result = run_hard_cases(study, run.progress);
    write_hard_case_tables(run.dir, study, result);
    StudyOutcome out;
    out.checks = checks_of(result);
    out.parameters = hard_cases_parameters(study, run.quick, 0);
    out.parameters["cases_summary"] = case_summary_json(result);
    out.summary = fmt::format("{} cases", result.case_summary.size());
    return out;
  };
}

const RegisterStudyKind kHardCases{"hard_cases", parse_hard_cases};

}  // namespace
}  // namespace vrv
