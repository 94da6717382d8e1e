#include "lib/projection/projection_reference.h"

#include <stdexcept>

#include <fmt/format.h>

#include "lib/option_error.h"

namespace vrv {

void validate(const ProjectionOptions& options) {
  if (!(options.tol > 0) || !std::isfinite(options.tol))
    throw OptionError(Option::tol, fmt::format("must be a positive finite number, got {}", options.tol));
}

ProjectionResult projection_reference(const Scene& scene, const Ray& ray, ProjectionMode mode,
                                      const ProjectionOptions& options) {
  return visit_field(scene, [&](const auto& field) {
    return projection_reference(field, scene.box, scene.transfer, ray, mode, options);
  });
}

}  // namespace vrv
