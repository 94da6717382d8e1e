#pragma once
// Study kind "shading" (issue 25): what gradient reconstruction costs a shaded raycast in accuracy.
// Marschner-Lobb (designed to test gradient reconstruction, Marschner & Lobb 1994) with a
// [shading] table, each gradient scheme (lib/gradient_scheme.h) against the shaded reference:
//   step refinement on the analytic field: mean error, and the same rule's error unshaded (what
//   shading adds), and each scheme's observed order;
//   grid refinement: the field sampled on n^3 node grids, the step a fixed fraction of the
//   spacing, each scheme against the grid scene's own shaded reference, and the observed order
//   in the spacing;
//   images: the shaded reference of the analytic field and of one grid, and each scheme's signed
//   error map at one step (with the unshaded raycast's on the analytic field: what shading adds).
// Read from shading.toml; run by driver.cpp.
#include <filesystem>
#include <string>
#include <vector>

#include "lib/discrete_raycast.h"
#include "lib/io/image_io.h"
#include "lib/metrics.h"
#include "lib/order_estimate.h"
#include "lib/scene.h"
#include "studies/engine/reference_audit.h"
#include "studies/engine/study_driver.h"
#include "studies/engine/study_work.h"

namespace vrv {

// A way of shading the study compares: a gradient scheme, shading at the samples, or
// "shaded_nodes": shading at a grid's nodes with their node differences, pre-classified, the
// shaded classes interpolated (DiscreteConfig::shade_at).  Grid-only ways are left out of the
// analytic field's parts.
struct ShadingScheme {
  GradientScheme gradient = GradientScheme::central;
  ShadeAt shade_at = ShadeAt::samples;
  std::string name() const;
  bool grid_only() const { return gradient == GradientScheme::nodes; }
};

struct ShadingStudy {
  std::string name, description;
  Scene scene;  // analytic, with [shading]
  SegmentRule rule = SegmentRule::trapezoid;
  std::vector<ShadingScheme> schemes;
  std::vector<double> steps;
  std::vector<int> grids;           // nodes per axis of the refined grids
  double grid_step_per_spacing = 0.25;
  double expected_order = 2;        // the analytic gradient's under step refinement (checked)
  int image_size = 64, quick_image_size = 16;  // pixels per side of the images (the scene's camera)
  double image_step = 0.01;                    // the images' step
  int image_grid = 33;                         // nodes per axis of the grid imaged
  long rays = 48, quick_rays = 12;
  std::uint64_t seed = 25;
  double reference_tol = 1e-11;
  OrderTolerance order_tolerance;
};

struct ShadingStepRow {
  std::string scheme;
  double step = 0, mean_error = 0, max_error = 0, unshaded_mean_error = 0;
};
struct ShadingGridRow {
  std::string scheme;
  int nodes = 0;
  double spacing = 0, step = 0, mean_error = 0, max_error = 0;
};
struct ShadingOrder {
  std::string refinement, scheme;
  OrderEstimate fit;
};
struct ShadingImageRow {  // one error map's statistics over the pixels that hit the box
  std::string field, scheme;  // "analytic" or "grid 33^3"; a gradient scheme or "unshaded"
  double step = 0;
  ErrorStats error;
};
struct ShadingImage {
  std::string stem;    // written as images/<stem>.exr and .png
  Image pixels;
  bool error = false;  // a signed error map (its colour bar shared by the field's maps), else values
  double range = 0;    // error maps: the colour bar's +-range (the maps' largest 99.5 % quantile)
};
struct ShadingResult {
  long rays = 0;
  std::vector<ShadingImageRow> image_rows;
  std::vector<ShadingImage> images;
  std::vector<ShadingStepRow> steps;
  std::vector<ShadingGridRow> grids;
  std::vector<ShadingOrder> orders;
  ReferenceAuditCounts truths;  // every reference the study computed
};

ShadingStudy read_shading_study(const StudyInput& in);
ShadingResult run_shading(const ShadingStudy& study, bool quick);
// steps.{csv,md,tex}, grids.{csv,md,tex}, orders.{csv,md,tex}, image_errors.{csv,md,tex},
// images/*.{exr,png} and plots.json in `dir`.
void write_shading(const std::filesystem::path& dir, const ShadingResult& result);
std::vector<StudyCheck> shading_checks(const ShadingStudy& study, const ShadingResult& result);
StudyWork shading_work(const ShadingStudy& study, bool quick);

}  // namespace vrv
