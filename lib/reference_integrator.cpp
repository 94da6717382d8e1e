#include "lib/reference_integrator.h"

#include <stdexcept>

#include <fmt/format.h>

#include "lib/option_error.h"

namespace vrv {

void check_tolerance(double tol) {
  if (!(tol > 0) || !std::isfinite(tol))
    throw OptionError(Option::tol, fmt::format("must be a positive finite number, got {}", tol));
}

void validate(const ReferenceOptions& options) { check_tolerance(options.tol); }

ReferenceResult integrate_reference(const Scene& scene, const Ray& ray,
                                    const ReferenceOptions& options) {
  return visit_field(scene, [&](const auto& field) {
    return integrate_reference(field, scene.box, scene.transfer, scene.background, ray, options,
                               scene.shading_or_null());
  });
}

}  // namespace vrv
