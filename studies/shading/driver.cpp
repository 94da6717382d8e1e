// Study kind "shading" (studies/shading/shading.h) as a study driver.
#include <fmt/format.h>

#include "studies/engine/study_driver.h"
#include "studies/shading/shading.h"

namespace vrv {
namespace {

StudyPlan parse_shading(const StudyInput& in) {
  ShadingStudy study = read_shading_study(in);
  StudyJob job = [study](const StudyRun& run) {
    const ShadingResult result = run_shading(study, run.quick);
    run.audit.record(result.truths);
    write_shading(run.dir, result);
    StudyOutcome out;
    out.checks = shading_checks(study, result);
    out.parameters = {{"rays", result.rays}, {"steps", study.steps}, {"grids", study.grids},
                      {"reference_tol", study.reference_tol}, {"seed", study.seed}};
    out.summary = fmt::format("{} rays, {} gradient schemes", result.rays, study.schemes.size());
    return out;
  };
  return {std::move(job), [study](bool quick) { return shading_work(study, quick); }};
}

// The refinement's node grids (one at a time: the largest) and the images' grid.
std::vector<NodeCounts> shading_grids(const toml::table& doc) {
  std::vector<NodeCounts> out;
  if (const auto cube = largest_cube(doc, "grids")) out.push_back(*cube);
  const std::int64_t n = ShadingStudy{}.image_grid;
  out.push_back(largest_cube(doc, "image_grid").value_or(NodeCounts{n, n, n}));
  return out;
}

const RegisterStudyKind kShading{"shading", parse_shading, shading_grids};

}  // namespace
}  // namespace vrv
