#pragma once
// Study kind "opacity_correction" (Lee & Newman, WSCG 2007): the study file as read, and the run.
// See studies/opacity-correction/opacity-correction.toml and docs/study-opacity-correction.md.
#include <cstdint>
#include <map>
#include <vector>

#include "studies/engine/study_driver.h"
#include "studies/opacity-correction/render.h"
#include "studies/opacity-correction/voxel.h"

namespace vrv {

struct OpacityStudy {
  std::vector<Correction> corrections;
  std::vector<bool> placements;  // false: oversamples from the unit sample on; true: centred
  double scale = 255, unit = 0;
  std::vector<double> oversamples;
  long csv_stride = 5;
  std::vector<int> fit_N;
  long fit_groups = 0, fit_quick_groups = 0;
  std::uint64_t fit_seed = 0;
  double threshold = 0.1;
  RenderScenes scenes;
  Camera camera;
  int render_N = 5, quick_width = 0, quick_height = 0;
  double error_map_quantile = 0.95;
  std::map<Correction, double> paper_render;
  std::vector<int> sweep_N;
  long rays = 0, quick_rays = 0;
  std::uint64_t sweep_seed = 0;
  int timing_N = 5;
  long timing_groups = 0, timing_quick_groups = 0;
  int repeats = 1, quick_repeats = 1, timing_w = 0, timing_h = 0, timing_qw = 0, timing_qh = 0;
  int render_repeats = 1, quick_render_repeats = 1;
  double paper_correction = 0, paper_overall = 0;
  double b_identity = 0, b_quadratic = 0, b_fit_mean = 0, b_comparable = 0, b_plateau = 0;
  OrderTolerance order_tolerance;
};

// Every key checked; throws StudyFileError (one line naming file and key).
OpacityStudy read_opacity_study(const StudyInput& in);
// Runs every part, writes tables, images and plots.json into run.dir, returns the checks.
StudyOutcome run_opacity_study(const OpacityStudy& s, const StudyRun& run);
// Field evaluations of the run (full or `quick`): the renders, the sweep and the timed renders.
StudyWork opacity_work(const OpacityStudy& s, bool quick);

}  // namespace vrv
