#pragma once
// The one way to make a reference image: the reference integral at every pixel of a camera
// (or a subset of them) through the image loop.  Render, verify and the library each keep what
// they need of a pixel's ReferenceResult (value, error estimate, evaluations, optical depth,
// whether the tolerance was met), so none of them holds more per pixel than it uses.
#include <functional>
#include <span>

#include "lib/camera.h"
#include "lib/image_loop.h"
#include "lib/reference_integrator.h"
#include "lib/scene.h"

namespace vrv {

// Called once per position, from any thread (each position its own slot).
using ReferencePut = std::function<void(long position, const ReferenceResult& result)>;

// options as given (the caller validates them); positions as image_loop_into numbers them.
void reference_pixels(const Scene& scene, const Camera& camera, const ReferenceOptions& options,
                      const ReferencePut& put, const ImageLoopHooks& hooks = {}, std::span<const long> subset = {});

}  // namespace vrv
