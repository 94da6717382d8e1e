#pragma once
// The diagnosis: vrv casts its own models of a renderer (model_catalogue.h) at the images' steps
// and lists them by RMS difference from the images, nearest first.
#include <vector>

#include "lib/camera.h"
#include "lib/discrete_raycast.h"
#include "lib/scene.h"
#include "lib/verify/verify_inputs.h"
#include "lib/verify/verify_report.h"

namespace vrv {

// The catalogue's models against channel `channel` of the images `sorted` (by decreasing step);
// models whose pixels equal an earlier one's are left out.
std::vector<Candidate> diagnose(const Scene& scene, const Camera& camera,
                                const std::vector<const ImageWithStep*>& sorted, int channel,
                                const VerifyOptions& options);

// A discrete raycast of the given pixels (row-major indices) of `camera`.
std::vector<double> cast_pixels(const Scene& scene, const Camera& camera, const DiscreteConfig& config,
                                const std::vector<long>& pixels);

// A discrete raycast of every pixel (vrv's own model of a renderer).
std::vector<double> discrete_image(const Scene& scene, const Camera& camera, const DiscreteConfig& config);

}  // namespace vrv
