// The two table-driven kinds of lib/study.h as study drivers: "convergence" (observed against
// expected orders, Etiene et al. TVCG 2014) and "hard_cases" (stability cases).
#include <cmath>
#include <sstream>

#include <fmt/format.h>

#include "lib/atomic_file.h"
#include "lib/study.h"
#include "studies/study_driver.h"

namespace vrv {
namespace {

StudyDefinition definition(const StudyInput& in) {
  std::ostringstream text;
  text << in.doc;
  return parse_study(text.str(), in.reader.source(), in.name);
}

std::vector<StudyCheck> checks_of(const StudyDefinition& study, const StudyResult& result) {
  std::vector<StudyCheck> checks;
  for (const OrderRow& o : result.orders)
    checks.push_back(order_check(fmt::format("order {}", segment_rule_name(o.rule)), o.fit, o.expected,
                                 study.order_tolerance));
  for (const GridOrderRow& o : result.grid_orders)
    checks.push_back(order_check(fmt::format("grid order {}", o.method), o.fit, o.expected, study.order_tolerance));
  // Hard cases: a row with a bound (the reference's own estimate, or a stated max_error whose
  // derivation is next to it in the study file) checks the error against it; a row without one
  // is a finiteness check only, and says so.
  for (const CaseRow& r : result.cases) {
    const bool bounded = std::isfinite(r.bound);
    std::string detail = !r.finite  ? std::string("value not finite")
                         : r.reference ? "error against the truth within the reference's own estimate (+ the truth's), "
                                         "estimate within its tol"
                         : bounded     ? "error against the reference within the stated max_error (derived in the file)"
                                       : fmt::format("finiteness only: no error bound stated (error {:.3g}, recorded "
                                                     "in cases.csv)", r.error);
    checks.push_back({fmt::format("{} / {}{}", r.case_name, r.method, bounded || !r.finite ? "" : ": finite"),
                      r.error, r.bound, r.pass, std::move(detail), CheckKind::derived});
  }
  return checks;
}

// The convergence plot: mean error against step per method, log-log with fitted slopes.
constexpr const char* kConvergencePlots = R"json({
  "plots": [
    {"name": "convergence", "csv": "errors.csv", "style": "lines", "x": "step", "y": "mean_error",
     "group": "method", "xscale": "log", "yscale": "log", "fit": true,
     "xlabel": "step (world units)", "ylabel": "mean |discrete - reference|",
     "title": "Convergence against step"}
  ]
}
)json";

constexpr const char* kGridPlots = R"json({
  "plots": [
    {"name": "convergence", "csv": "errors.csv", "style": "lines", "x": "step", "y": "mean_error",
     "group": "method", "xscale": "log", "yscale": "log", "fit": true,
     "xlabel": "step (world units)", "ylabel": "mean |discrete - reference|",
     "title": "Convergence against step"},
    {"name": "grid_convergence", "csv": "grid_errors.csv", "style": "lines", "x": "cell",
     "y": "mean_error", "group": "method", "xscale": "log", "yscale": "log", "fit": true,
     "xlabel": "grid cell size (world units; discrete step tied to it)",
     "ylabel": "mean |value - analytic reference|", "title": "Convergence under grid refinement"}
  ]
}
)json";

StudyJob parse_table_study(const StudyInput& in) {
  StudyDefinition study = definition(in);
  return [study](const StudyRun& run) {
    const StudyResult result = run_convergence(study, run.quick, run.progress);
    write_study_tables(run.dir, study, result);
    StudyOutcome out;
    out.checks = checks_of(study, result);
    out.parameters = study_parameters(study, run.quick, 0);
    if (study.kind == "hard_cases") {
      out.parameters["cases_summary"] = case_summary_json(result);
      out.summary = fmt::format("{} cases", result.case_summary.size());
    } else {
      write_file_atomically(run.dir / "plots.json",
                            result.grid_errors.empty() ? kConvergencePlots : kGridPlots);
      out.summary = fmt::format("{} rays, {} methods", result.rays, study.methods.size());
    }
    return out;
  };
}

const RegisterStudyKind kConvergence{"convergence", parse_table_study};
const RegisterStudyKind kHardCases{"hard_cases", parse_table_study};

}  // namespace
}  // namespace vrv
