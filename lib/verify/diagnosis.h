#pragma once
// The diagnosis: vrv casts its own models of a renderer (model_catalogue.h) at the images' steps
// and lists them by RMS difference from the images, nearest first.  Coarse to fine: the distinct
// models (the same configuration listed twice is cast once) are ranked on kRankingPixels pixels,
// and only the leaders are cast on the kDiagnosisPixels the report's numbers come from; the
// (model, step) casts run in parallel, each into its own slot, so the report does not depend on
// the thread count.
#include <cstddef>
#include <vector>

#include "lib/camera.h"
#include "lib/discrete_raycast.h"
#include "lib/scene.h"
#include "lib/verify/model_catalogue.h"
#include "lib/verify/verify_inputs.h"
#include "lib/verify/verify_report.h"

namespace vrv {

// Pixels the report's numbers come from: all of them up to 128 x 128, else a regular lattice of
// about that many, so that the diagnosis stays a matter of seconds.
inline constexpr long kDiagnosisPixels = 16384;
// Pixels every model is ranked on: a regular lattice of about 32 x 32 over the image.
inline constexpr long kRankingPixels = 1024;
// The leaders confirmed on the diagnosis pixels: the first kMinLeaders of the ranking, and every
// other model within kLeaderFactor of the best's ranking RMS.
inline constexpr std::size_t kMinLeaders = 3;
inline constexpr double kLeaderFactor = 10;

// Row-major pixel indices of a w x h image: the lattices above.
std::vector<long> diagnosis_pixels(int width, int height);
std::vector<long> ranking_pixels(int width, int height);

// The catalogue for images at `steps` without the models that repeat an earlier one's
// configuration (same_model, model_catalogue.h).
std::vector<Model> distinct_models(const Scene& scene, const std::vector<double>& steps, const VerifyOptions& options);

// The distinct models against channel `channel` of the images `sorted` (by decreasing step).  On a
// shaded scene the models take the gradient scheme nearest the finest image (each scheme with the
// ranking's first kMinLeaders models, on the ranking pixels; ranked again with it), and the
// ranking's nearest model is also cast with each other scheme (gradient_variants), as leaders.
// The leaders first, by their RMS on the diagnosis pixels, then the others by their RMS on the ranking
// pixels (Candidate::pixels says which); a model whose pixels equal an earlier one's to rounding
// is left out.
std::vector<Candidate> diagnose(const Scene& scene, const Camera& camera,
                                const std::vector<const ImageWithStep*>& sorted, int channel,
                                const VerifyOptions& options);

// Field samples the diagnosis takes for images of `camera` at `steps`: every distinct model on the
// ranking pixels and kMinLeaders of them (the dearest) on the diagnosis pixels, from each
// configuration's camera_work (lib/work_estimate.h).  More leaders (within kLeaderFactor) add to it.
double diagnosis_work(const Scene& scene, const Camera& camera, const std::vector<double>& steps,
                      const VerifyOptions& options);

// A discrete raycast of the given pixels (row-major indices) of `camera`.
std::vector<double> cast_pixels(const Scene& scene, const Camera& camera, const DiscreteConfig& config,
                                const std::vector<long>& pixels);

// A discrete raycast of every pixel (vrv's own model of a renderer).
std::vector<double> discrete_image(const Scene& scene, const Camera& camera, const DiscreteConfig& config);

}  // namespace vrv
