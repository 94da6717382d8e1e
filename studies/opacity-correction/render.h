#pragma once
// The opacity-correction study's raycasts (Lee & Newman, WSCG 2007, Fig. 7 and Table 1): an
// oversampled alpha-rule render of a sampled grid against the reference integral of the analytic
// field it was sampled from, the error against the continuous integral as N grows, the
// oversampled render's own sample groups (for the fit error) and the time of whole renders.
#include <cstdint>
#include <string>
#include <vector>

#include "lib/camera.h"
#include "lib/discrete_raycast.h"
#include "lib/io/image_io.h"
#include "lib/metrics.h"
#include "lib/scene.h"
#include "studies/engine/reference_audit.h"

namespace vrv {

class Checkpoints;  // studies/engine/checkpoint.h

// The paper's raycaster in vrv's terms: alpha rule, samples a fixed world step apart (the unit
// step, one voxel; first sample half a step inside), N oversamples per unit step, correction c;
// the oversamples start at the unit sample (the paper's alpha_u1 = alpha_o1) or are centred.
DiscreteConfig oversampled_config(Correction c, int N, double unit_step, bool centred);

// `analytic`: the scene with its analytic field (the reference integrates it); `sampled`: the
// same scene with the grid the discrete renders read.
struct RenderScenes {
  Scene analytic, sampled;
  double unit_step = 1;
  double reference_tol = 1e-8;
};

struct RenderMethod {
  std::string label;
  Correction correction = Correction::none;
  int N = 1;
  bool centred = false;
};

// Every pixel of `camera` (row-major, row 0 at the top): the reference value and each method's
// discrete value, parallel over pixels, each into its own slot; worst_estimate is the largest
// error estimate the reference reported.
struct RenderValues {
  std::vector<double> reference;
  std::vector<std::vector<double>> methods;
  double worst_estimate = 0;
};
// With checkpoints, each image row is stored (--resume); the truths are counted in `audit`.
RenderValues render_values(const RenderScenes& s, const Camera& camera, const std::vector<RenderMethod>& methods,
                           bool progress, Checkpoints* checkpoints, ReferenceAudit& audit);
Image to_image(const std::vector<double>& values, int width, int height);

// Mean, max and root-mean-square of |a - b| over the pixels (sums in index order; p99 not taken).
ErrorStats pixel_difference(const std::vector<double>& a, const std::vector<double>& b);

// The opacities of the oversampled render's full groups of N along every pixel ray (grid field,
// the scene's opacity curve; concatenated in pixel order): what the quadratic fit meets in use.
std::vector<double> render_groups(const RenderScenes& s, const Camera& camera, int N, bool centred);

// Error against the continuous integral (the analytic field's reference) over rays, per
// (correction, N).  max_diff_from_none: max over rays of |value - value with correction none| at
// the same N (0 at N = 1 for every correction, as no correction changes a group of one).
struct SweepRow {
  Correction correction = Correction::none;
  int N = 1;
  bool centred = false;
  double mean_error = 0, max_error = 0, max_diff_from_none = 0;
  bool finite = true;
};
std::vector<SweepRow> error_against_N(const RenderScenes& s, const std::vector<Ray>& rays,
                                      const std::vector<Correction>& corrections, const std::vector<int>& Ns,
                                      bool centred, bool progress, Checkpoints* checkpoints, ReferenceAudit& audit);

// Table 1, lower row: seconds for one serial pass of the discrete render (every pixel of
// camera), the best of `repeats`.
double render_seconds(const RenderScenes& s, const Camera& camera, const DiscreteConfig& config, int repeats);

}  // namespace vrv
