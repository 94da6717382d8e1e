#pragma once
// The fitted fault catalogue: a step-independent floor decomposed into parametrised faults.  Each
// entry is a perturbation of vrv's nearest model of the renderer (its camera, box, transfer
// function, opacity, termination, interpolation) or of its image (flips, transpose, output curve)
// with at most one parameter, fitted by least squares to the finest image on a pixel subset (the
// ranking lattice, diagnosis.h); the entries are ranked by the fraction of the floor's squared
// error they explain, and the leaders are confirmed on the diagnosis pixels.  An entry is declared
// in one place (fault_fit.cpp, kEntries): its parameter and bracket, its perturbation and its
// description.
#include <limits>
#include <string>
#include <vector>

#include "lib/camera.h"
#include "lib/discrete_raycast.h"
#include "lib/scene.h"
#include "lib/verify/verify_inputs.h"
#include "lib/verify/verify_options.h"
#include "lib/verify/verify_report.h"

namespace vrv {

// The leaders confirmed on the diagnosis pixels, and the confirmed fraction an entry needs to be
// named as the fault.
inline constexpr std::size_t kConfirmedFits = 3;
inline constexpr double kNamedFraction = 0.8;

// What the fits read: vrv's nearest model of the renderer at the finest image's step, and that image.
struct FitInput {
  const Scene& scene;
  const Camera& camera;
  DiscreteConfig model;
  const ImageWithStep& finest;
  int channel = 0;
  AlphaMode alpha = AlphaMode::premultiplied;
};

// Every entry that applies to the scene and camera, fitted and ranked (best confirmed first).
std::vector<FaultFit> fit_faults(const FitInput& input);

// The identifiers of the catalogue's entries ("rows_flipped", "fov_scale", ...), in its order.
std::vector<std::string> fault_fit_ids();

// When the images stall at a floor (the reference verdict stalls, or a constant floor is named):
// fits the catalogue on top of vrv's model of the renderer's discretisation (of the models whose
// opacity is corrected, the one whose differences between successive steps match the images':
// the floor cancels in them; on a shaded scene with the gradient scheme of report.diagnosis's
// nearest model), fills report.fault_fits and names the best confirmed entry that explains at least kNamedFraction as a
// fault.  Nothing otherwise, or with options.diagnose off.
void decompose_floor(VerifyReport& report, const Scene& scene, const std::vector<const ImageWithStep*>& sorted,
                     int channel, const VerifyOptions& options);

}  // namespace vrv
