// Study kind "convergence" (studies/convergence/convergence.h) as a study driver: observed
// against expected orders (Etiene et al. TVCG 2014), under step and, optionally, grid refinement.
#include <fmt/format.h>

#include "lib/io/atomic_file.h"
#include "studies/convergence/convergence.h"
#include "studies/engine/checkpoint.h"
#include "studies/engine/study_driver.h"

namespace vrv {
namespace {

std::vector<StudyCheck> checks_of(const StudyDefinition& study, const StudyResult& result) {
  std::vector<StudyCheck> checks;
  for (const OrderRow& o : result.orders)
    checks.push_back(order_check(fmt::format("order {}", segment_rule_name(o.rule)), o.fit, o.expected,
                                 study.order_tolerance));
  for (const GridOrderRow& o : result.grid_orders)
    checks.push_back(order_check(fmt::format("grid order {}", o.method), o.fit, o.expected, study.order_tolerance));
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

StudyPlan parse_convergence(const StudyInput& in) {
  StudyDefinition study = read_convergence_study(in);
  StudyJob job = [study](const StudyRun& run) {
    const StudyResult result =
        run_convergence(study, run.quick, run.audit, run.progress, checkpoint_function(run.checkpoints));
    write_study_tables(run.dir, study, result);
    StudyOutcome out;
    out.checks = checks_of(study, result);
    out.parameters = study_parameters(study, run.quick, 0);
    write_file_atomically(run.dir / "plots.json",
                          result.grid_errors.empty() ? kConvergencePlots : kGridPlots);
    out.summary = fmt::format("{} rays, {} methods", result.rays, study.methods.size());
    return out;
  };
  return {std::move(job), [study](bool quick) { return convergence_work(study, quick); }};
}

// [grid_refinement]'s grids, built one at a time from one of its lists.
std::vector<NodeCounts> convergence_grids(const toml::table& doc) {
  const toml::table* g = doc.get_as<toml::table>("grid_refinement");
  if (!g) return {};
  std::vector<NodeCounts> out;
  for (std::string_view key : {"resolutions", "quick_resolutions"})
    if (const auto cube = largest_cube(*g, key); cube && (out.empty() || (*cube)[0] > out[0][0])) out = {*cube};
  return out;
}

const RegisterStudyKind kConvergence{"convergence", parse_convergence, convergence_grids};

}  // namespace
}  // namespace vrv
