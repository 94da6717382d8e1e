// Study kind "projections" (studies/projections/projections.h) as a study driver.
#include <fmt/format.h>

#include "studies/engine/study_driver.h"
#include "studies/projections/projections.h"

namespace vrv {
namespace {

StudyPlan parse_projections(const StudyInput& in) {
  ProjectionsStudy study = read_projections_study(in);
  StudyJob job = [study](const StudyRun& run) {
    const ProjectionsResult result = run_projections(study, run.quick);
    write_projections(run.dir, study, result);
    const ProjectionsImages images = run_projections_images(study, run.quick);
    run.audit.record(result.truths);
    run.audit.record(images.truths);
    write_projections_images(run.dir, images);
    StudyOutcome out;
    out.checks = projections_checks(study, result);
    for (StudyCheck& c : images_checks(study, images)) out.checks.push_back(std::move(c));
    out.parameters = {{"rays", result.rays}, {"steps", study.steps}, {"reference_tol", study.reference_tol},
                      {"seed", study.seed}, {"image_width", images.width}, {"image_height", images.height}};
    out.summary = fmt::format("{} rays, {} methods", result.rays, study.methods.size());
    return out;
  };
  return {std::move(job), [study](bool quick) { return projections_work(study, quick); }};
}

const RegisterStudyKind kProjections{"projections", parse_projections};

}  // namespace
}  // namespace vrv
