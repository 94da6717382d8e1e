#pragma once
// Study kind "projections" (issue 26): the error and observed order of discrete X-ray and MIP
// projections under step refinement, against their references (lib/projection/), with the orders
// theory expects.  Read from projections.toml; run by driver.cpp.
#include <filesystem>
#include <string>
#include <vector>

#include "lib/order_estimate.h"
#include "lib/projection/discrete_projection.h"
#include "lib/scene.h"
#include "studies/engine/study_driver.h"
#include "studies/engine/study_work.h"

namespace vrv {

struct ProjectionsMethod {
  std::string label;  // e.g. "mip max step"
  DiscreteProjectionConfig config;  // sampling.step set per step
  double expected_order = 0;
  // MIP only: the rays whose reference maximum lies where the order is expected: "interior" (more
  // than twice the largest step inside), "face" (at the entry or exit), or "all".
  std::string maxima = "all";
};

struct ProjectionsStudy {
  std::string name, description;
  Scene scene;
  std::vector<ProjectionsMethod> methods;
  std::vector<double> steps;
  long rays = 64, quick_rays = 16;
  std::uint64_t seed = 26;
  double reference_tol = 1e-13;
  OrderTolerance order_tolerance;
};

struct ProjectionsRow {
  std::string method;
  long rays = 0;  // the rays of the method's `maxima` class
  double step = 0, mean_error = 0, max_error = 0;
};
struct ProjectionsOrder {
  std::string method;
  double expected = 0;
  OrderEstimate fit;
};
struct ProjectionsResult {
  long rays = 0;
  std::vector<ProjectionsRow> errors;
  std::vector<ProjectionsOrder> orders;
  double max_reference_estimate = 0;  // over every mode's reference on every ray
  long references_missed = 0;         // references whose estimate missed reference_tol
};

ProjectionsStudy read_projections_study(const StudyInput& in);
ProjectionsResult run_projections(const ProjectionsStudy& study, bool quick);
// errors.{csv,md,tex}, orders.{csv,md,tex} and plots.json in `dir`.
void write_projections(const std::filesystem::path& dir, const ProjectionsStudy& study, const ProjectionsResult& result);
std::vector<StudyCheck> projections_checks(const ProjectionsStudy& study, const ProjectionsResult& result);
StudyWork projections_work(const ProjectionsStudy& study, bool quick);

}  // namespace vrv
