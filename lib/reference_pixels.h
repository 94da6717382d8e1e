#pragma once
// The one way to make a reference image: the reference integral at every pixel of a camera
// (or a subset of them) through the image loop.  Render, verify and the library each keep what
// they need of a pixel's ReferenceResult (value, error estimate, evaluations, optical depth,
// whether the tolerance was met), so none of them holds more per pixel than it uses.
// A template in the header, so the integrator is compiled in the caller's unit: in the
// position-independent vrvcore, `vrv render --reference` on a grid ran about 10 % slower.
#include <span>

#include "lib/camera.h"
#include "lib/image_loop.h"
#include "lib/reference_channels.h"
#include "lib/reference_integrator.h"
#include "lib/scene.h"

namespace vrv {

// put(position, result) once per position, from any thread (each position its own slot);
// options as given (the caller validates them); positions as image_loop_into numbers them.
template <class Put>
void reference_pixels(const Scene& scene, const Camera& camera, const ReferenceOptions& options, Put&& put,
                      const ImageLoopHooks& hooks = {}, std::span<const long> subset = {}) {
  visit_field(scene, [&](const auto& field) {
    image_loop_into(
        camera, subset,
        [&](const Ray& ray) {
          return integrate_reference(field, scene.box, scene.transfer, scene.background, ray, options,
                                     scene.shading_or_null());
        },
        put, hooks);
  });
}

// The channels of an image (ImageChannels: grey or RGB, and alpha where asked) from one walk per
// ray: put(position, keep(ChannelsReferenceResult)).  `keep` reduces a pixel to what the caller
// holds, which under MPI is the record the ranks exchange (std::identity keeps it whole).
template <class Keep, class Put>
void image_channel_pixels(const Scene& scene, const Camera& camera, const ImageChannels& channels,
                          const ReferenceOptions& options, Keep&& keep, Put&& put, const ImageLoopHooks& hooks = {},
                          std::span<const long> subset = {}) {
  visit_field(scene, [&](const auto& field) {
    image_loop_into(
        camera, subset,
        [&](const Ray& ray) {
          return keep(integrate_image_channels(field, scene.box, channels, ray, options, scene.shading_or_null()));
        },
        put, hooks);
  });
}

}  // namespace vrv
