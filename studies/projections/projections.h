#pragma once
// Study kind "projections" (issue 26): the error and observed order of discrete X-ray and MIP
// projections under step refinement, against their references (lib/projection/), with the orders
// theory expects.  Read from projections.toml; run by driver.cpp.
#include <filesystem>
#include <string>
#include <vector>

#include "lib/io/image_io.h"
#include "lib/order_estimate.h"
#include "lib/projection/discrete_projection.h"
#include "lib/scene.h"
#include "studies/engine/reference_audit.h"
#include "studies/engine/study_driver.h"
#include "studies/engine/study_work.h"

namespace vrv {

struct ProjectionsMethod {
  std::string label;  // e.g. "mip max step"
  DiscreteProjectionConfig config;  // sampling.step set per step
  double expected_order = 0;
  // MIP only: the rays whose reference maximum lies where the order is expected: "interior" (more
  // than twice the largest step inside), "face" (at the entry or exit), "entry", "exit", or "all".
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
  int image_size = 128, quick_image_size = 32;  // the images' side in pixels (scene's camera)
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
  ReferenceAuditCounts truths;  // every mode's reference on every ray
};

// The images (images.cpp): each mode's reference image, each method's error map at the coarsest step.
struct ProjectionsErrorMap {
  std::string method, file_stem;
  double step = 0, rms_error = 0, max_error = 0;
  Image error;  // discrete - reference per pixel
};
struct ProjectionsImages {
  int width = 0, height = 0;
  std::vector<std::pair<std::string, Image>> references;  // (mode name, image)
  std::vector<ProjectionsErrorMap> error_maps;  // one per distinct cast (mode, method, strategy)
  ReferenceAuditCounts truths;  // every mode's reference on every pixel
};

ProjectionsStudy read_projections_study(const StudyInput& in);
ProjectionsResult run_projections(const ProjectionsStudy& study, bool quick);
// errors.{csv,md,tex}, orders.{csv,md,tex} and plots.json in `dir`.
void write_projections(const std::filesystem::path& dir, const ProjectionsStudy& study, const ProjectionsResult& result);
ProjectionsImages run_projections_images(const ProjectionsStudy& study, bool quick);
// images/<mode>_reference.{exr,png}, images/<method>_error.{exr,png}, error_maps.{csv,md,tex}.
void write_projections_images(const std::filesystem::path& dir, const ProjectionsImages& images);
// "finite image errors" (every error map's RMS and largest error finite: a NaN is never silent) and
// "image references within reference_tol".
std::vector<StudyCheck> images_checks(const ProjectionsStudy& study, const ProjectionsImages& images);
std::vector<StudyCheck> projections_checks(const ProjectionsStudy& study, const ProjectionsResult& result);
StudyWork projections_work(const ProjectionsStudy& study, bool quick);
// The images' share of it.
void add_images_work(const ProjectionsStudy& study, bool quick, StudyWork& work);

}  // namespace vrv
