#pragma once
// Verifying projection images (`vrv verify --mode`, docs/projections.md): what differs from an
// emission-absorption verification.  The reference per pixel is the projection reference
// (lib/projection/projection_reference.h); the nearest-model diagnosis casts vrv's discrete
// projections (lib/projection/discrete_projection.h) at the images' steps, every placement x
// rule (MIP: the largest sample); the emission-absorption fault catalogue and conventions are
// not run (they model compositing and opacity, which a projection has not).
#include <string>
#include <vector>

#include "lib/camera.h"
#include "lib/projection/discrete_projection.h"
#include "lib/projection/projection_mode.h"
#include "lib/scene.h"
#include "lib/verify/reference_image.h"
#include "lib/verify/verify_inputs.h"
#include "lib/verify/verify_options.h"
#include "lib/verify/verify_report.h"

namespace vrv {

// The order a mode's images are expected to converge at when none is given: 2, except 1 for a
// classified MIP whose extinction peaks at a corner. X-ray by the midpoint or trapezoid rule is
// second order in the step; a sampled MIP of a smooth field misses an interior maximum by O(h) in
// position and so O(h^2) in value; but where max tau(f) sits at a corner of tau (a breakpoint where
// tau rises, then falls), tau(f(s)) has a corner there too and a sample misses it by O(h) in value
// (the projections study: observed 1.01).
double expected_projection_order(ProjectionMode mode, const TransferFunction& tf);

// The reference image of a projection: value and error estimate per pixel (optical depth 0).
ReferenceImage projection_reference_image(const Scene& scene, const Camera& camera, ProjectionMode mode, double tol,
                                          bool progress);

// What joins the reference cache key of a projection (EA keys stay as they were).
std::string projection_cache_tag(ProjectionMode mode);

struct ProjectionModel {
  Candidate label;
  std::vector<DiscreteProjectionConfig> per_step;
};

// Every placement (the EA diagnosis's five) x rule (X-ray: riemann, trapezoid, simpson; MIP: max)
// at the images' steps.
std::vector<ProjectionModel> projection_models(const Scene& scene, ProjectionMode mode, const std::vector<double>& steps);

// The models against channel `channel` of `sorted` (by decreasing step) on the diagnosis pixels
// (lib/verify/diagnosis.h), nearest (RMS) first.
std::vector<Candidate> diagnose_projection(const Scene& scene, const Camera& camera, ProjectionMode mode,
                                           const std::vector<const ImageWithStep*>& sorted, int channel,
                                           const VerifyOptions& options);

// Field samples diagnose_projection takes for images of `camera` at `steps`: every model at every
// step on the diagnosis pixels, from each placement's camera_work (lib/work_estimate.h); Simpson's
// rule counted at twice its placement's samples (its midpoints).
double projection_diagnosis_work(const Scene& scene, const Camera& camera, ProjectionMode mode,
                                 const std::vector<double>& steps);

// The report's line saying what is skipped for a projection.
inline constexpr const char* kProjectionSkipNote =
    "projection: the emission-absorption fault catalogue and conventions are not run (they model compositing "
    "and opacity)";

}  // namespace vrv
