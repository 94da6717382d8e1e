#include "lib/projection/projection_reference.h"

#include "lib/reference_integrator.h"

namespace vrv {

void validate(const ProjectionOptions& options) { check_tolerance(options.tol); }

ProjectionResult projection_reference(const Scene& scene, const Ray& ray, ProjectionMode mode,
                                      const ProjectionOptions& options) {
  return visit_field(scene, [&](const auto& field) {
    return projection_reference(field, scene.box, scene.transfer, ray, mode, options);
  });
}

}  // namespace vrv
