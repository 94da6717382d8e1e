#include "lib/reference_pixels.h"

namespace vrv {

void reference_pixels(const Scene& scene, const Camera& camera, const ReferenceOptions& options,
                      const ReferencePut& put, const ImageLoopHooks& hooks, std::span<const long> subset) {
  visit_field(scene, [&](const auto& field) {
    image_loop_into(
        camera, subset,
        [&](const Ray& ray) {
          return integrate_reference(field, scene.box, scene.transfer, scene.background, ray, options);
        },
        put, hooks);
  });
}

}  // namespace vrv
