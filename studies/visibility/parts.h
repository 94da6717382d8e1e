#pragma once
// The four parts of the visibility study, each writing its own tables and images into the
// study's directory and returning its checks.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "lib/scene.h"
#include "studies/engine/study_driver.h"
#include "studies/visibility/identities.h"
#include "studies/visibility/culling.h"

namespace vrv {

struct VisibilityStudy {
  Scene scene;  // a grid field, emission/extinction transfer function
  std::string scene_toml;
  double radiance = 0;  // max(max colour, background): what any rest of a ray can add at most
  struct {
    std::vector<double> ks;
    PiecewiseLinear basis2;  // a second extinction basis (eq. 3)
    long rays = 64, quick_rays = 8;
    std::uint64_t seed = 2003;
    double step = 0.03125, reference_tol = 1e-13, max_error = 1e-13, max_transparency_error = 1e-12;
  } identity;
  struct {
    double alpha = 0.05, threshold = 0.95, paper_samples = 58.4, paper_rounding = 0.05;
    long ray_samples = 200;
  } samples;
  struct {
    std::vector<double> thresholds;
    long image = 64, quick_image = 16;
    double step = 0.03125, reference_tol = 1e-10;
  } termination;
  struct {
    std::array<int, 3> blocks{8, 8, 8};
    std::array<int, 2> views{36, 36}, quick_views{6, 6};
    long image = 32, quick_image = 16;
    double threshold = 0.95, step = 0.03125, chord_fraction = 0.5;
    int pof_block = 0;
    std::array<int, 2> image_view{0, 0};
  } culling;
};

struct IdentityResult {
  std::vector<StudyCheck> checks;
  long rays = 0;
  double max_difference = 0;
};
IdentityResult run_identity(const VisibilityStudy& s, const StudyRun& run);

struct SamplesResult {
  std::vector<StudyCheck> checks;
  long discrete_samples = 0;
};
SamplesResult run_threshold_samples(const VisibilityStudy& s, const StudyRun& run);

struct TerminationResult {
  std::vector<StudyCheck> checks;
  long side = 0;
};
TerminationResult run_termination(const VisibilityStudy& s, const StudyRun& run);

struct CullingResult {
  std::vector<StudyCheck> checks;
  int n_theta = 0, n_phi = 0;
  long side = 0;
  double mean_share_pof = 0, mean_share_chord = 0, mean_share_seq = 0, max_error = 0, bound = 0;
  std::string equator_phi_text;  // the phi of the rotation plot, as the CSV writes it
  int pof_block = 0;
};
CullingResult run_culling(const VisibilityStudy& s, const StudyRun& run);

// Field evaluations of the four parts (full or `quick`), estimated from the study alone.
StudyWork visibility_work(const VisibilityStudy& s, bool quick);

}  // namespace vrv
