#pragma once
// Study kind "error_prediction" (issue 29): the error each discrete raycast is predicted to have
// before the reference (the estimate, lib/discrete_error_estimate.h, and the a-priori bound,
// lib/discrete_error_bound.h) against the error measured with the reference, per ray, on the
// studies' scenes, every covered rule, placement and step.  Read from error-prediction.toml; run
// by driver.cpp; docs/study-error-prediction.md.
#include <filesystem>
#include <string>
#include <vector>

#include "lib/discrete_raycast.h"
#include "lib/scene.h"
#include "studies/engine/study_driver.h"
#include "studies/engine/study_work.h"

namespace vrv {

class Checkpoints;

struct ErrorPredictionCase {
  std::string name;
  Scene scene;
  std::vector<double> steps, quick_steps;
};

// One configuration cast at every step of every case: each rule with each placement, and the
// file's variants (oversampling, corrections, float, tables, termination, ...: what the bound and
// the estimate analyse through the nearest plain configuration, lib/discrete_error_bound.h).
struct PredictionMethod {
  std::string label;  // e.g. "alpha step", or the variant's label
  DiscreteConfig config;  // sampling.step set per step
};

struct ErrorPredictionStudy {
  std::vector<ErrorPredictionCase> cases;
  std::vector<PredictionMethod> methods;
  long rays = 64, quick_rays = 12;
  std::uint64_t seed = 29;
  double reference_tol = 1e-13;
  // Regression bounds the file declares with their measurement: the asymptotic rays' estimate miss
  // |estimate - error| / scale at the 99th percentile, and how many times the others' 90th
  // percentile must exceed the asymptotic rays' (the flag separates them).
  double asymptotic_miss = 0.05;
  double separation = 5;
};

// One ray of one configuration.
struct PredictionRay {
  double measured = 0;   // discrete - reference
  double estimated = 0;  // the estimate of it
  double bound = 0;      // |discrete - reference| <= bound, predicted
  double scale = 0;      // the estimate's error scale (no cancellation)
  bool asymptotic = false;
  double reference_estimate = 0;  // the reference's own error estimate
};

struct PredictionConfig {
  std::string case_name, method;
  DiscreteConfig config;
  std::vector<PredictionRay> rays;
};

struct ErrorPredictionResult {
  long rays = 0;
  std::vector<PredictionConfig> configs;
};

ErrorPredictionStudy read_error_prediction_study(const StudyInput& in);
// With the run's --quick, checkpoints and audit.
ErrorPredictionResult run_error_prediction(const ErrorPredictionStudy& study, const StudyRun& run);
// rays.csv (every ray), summary.{csv,md,tex} (per configuration), cases.{csv,md,tex} (per case),
// methods.{csv,md,tex} (per method),
// classes.{csv,md,tex} (pooled by the asymptotic flag) and plots.json in `dir`.
void write_error_prediction(const std::filesystem::path& dir, const ErrorPredictionResult& result);
std::vector<StudyCheck> error_prediction_checks(const ErrorPredictionStudy& study, const ErrorPredictionResult& result);
StudyWork error_prediction_work(const ErrorPredictionStudy& study, bool quick);

}  // namespace vrv
