#pragma once
// The reference image a renderer's images are judged against: every pixel's ray integrated to
// VerifyOptions::reference_tol, read from the on-disk cache when it holds it (reference_cache.h).
#include <string>
#include <vector>

#include "lib/camera.h"
#include "lib/io/image_io.h"
#include "lib/scene.h"
#include "lib/verify/verify_options.h"

namespace vrv {

// Per pixel (row-major, row 0 at the top): the value (the ImageF64's grey pixels), its error
// estimate and the optical depth.
struct ReferenceImage : ImageF64 {
  ReferenceImage() = default;
  // w x h pixels, every value, estimate and depth 0.
  ReferenceImage(int w, int h) : ImageF64(w, h), error_estimate(pixel_count()), optical_depth(pixel_count()) {}
  std::vector<double> error_estimate, optical_depth;
  bool from_cache = false;
  std::string cache_file;
};

// From the cache when options.cache_dir and options.scene_text are given and it holds this
// reference (then written there after computing it; a cache that cannot be written is said on
// stderr and does not fail the run); else computed, with a progress bar when options.progress.
ReferenceImage reference_image(const Scene& scene, const Camera& camera, const VerifyOptions& options);

// One reference image per scene channel: reference_image's for a grey scene; for an RGB scene the
// three channels from one walk per ray (image_channel_pixels), each cached as its own entry.
// An RGB scene with options.mode throws std::invalid_argument (a projection draws one channel).
std::vector<ReferenceImage> reference_images(const Scene& scene, const Camera& camera, const VerifyOptions& options);

}  // namespace vrv
