// Study kind "error_prediction" (studies/error-prediction/error_prediction.h) as a study driver.
#include <fmt/format.h>

#include "studies/engine/study_driver.h"
#include "studies/error-prediction/error_prediction.h"

namespace vrv {
namespace {

StudyPlan parse_error_prediction(const StudyInput& in) {
  ErrorPredictionStudy study = read_error_prediction_study(in);
  StudyJob job = [study](const StudyRun& run) {
    const ErrorPredictionResult result = run_error_prediction(study, run);
    write_error_prediction(run.dir, result);
    StudyOutcome out;
    out.checks = error_prediction_checks(study, result);
    out.parameters = {{"rays", result.rays}, {"configurations", result.configs.size()},
                      {"reference_tol", study.reference_tol}, {"seed", study.seed}};
    out.summary = fmt::format("{} configurations x {} rays", result.configs.size(), result.rays);
    return out;
  };
  return {std::move(job), [study](bool quick) { return error_prediction_work(study, quick); }};
}

const RegisterStudyKind kErrorPrediction{"error_prediction", parse_error_prediction};

}  // namespace
}  // namespace vrv
