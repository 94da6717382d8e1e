#pragma once
// The work limit of verification, shared by `vrv verify`, `vrv gate` and vrv.verify in Python:
// the same default and the same refusal wherever images are verified.
#include <string>
#include <vector>

#include "lib/scene.h"
#include "lib/verify.h"

namespace vrv {

// Work limit of verify and gate, as of ray and render (--max-work, field evaluations).
inline constexpr double kDefaultVerifyWorkLimit = 1e9;

// Refuses, before any work, a verification above `max_work` field evaluations: the reference on
// every pixel of images of width x height and the diagnosis (vrv's models cast at `steps`), as
// verification_work (lib/verify.h) estimates them, plus `renders` (a gate render case's own
// images).  std::invalid_argument "<who>: about ... above the work limit ..." naming `who`.
void check_verification_work(const Scene& scene, const VerifyOptions& options, int width, int height,
                             const std::vector<double>& steps, double renders, double max_work,
                             const std::string& who);

}  // namespace vrv
