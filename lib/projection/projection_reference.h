#pragma once
// The reference projection of a ray by mode (xray_reference.h, mip_reference.h), for one field
// type or for a scene (dispatched to its field's type).
#include "lib/projection/mip_reference.h"
#include "lib/projection/projection_mode.h"
#include "lib/projection/projection_result.h"
#include "lib/projection/xray_reference.h"
#include "lib/scene.h"

namespace vrv {

template <ScalarField F>
ProjectionResult projection_reference(const F& field, const Box& box, const TransferFunction& tf, const Ray& ray,
                                      ProjectionMode mode, const ProjectionOptions& options = {}) {
  const TransferFunction* classify = is_classified(mode) ? &tf : nullptr;
  return is_mip(mode) ? mip_reference(field, box, ray, options, classify)
                      : xray_reference(field, box, ray, options, classify);
}

// Throws OptionError (Option::tol) unless options.tol is positive and finite.
void validate(const ProjectionOptions& options);

ProjectionResult projection_reference(const Scene& scene, const Ray& ray, ProjectionMode mode,
                                      const ProjectionOptions& options = {});

}  // namespace vrv
