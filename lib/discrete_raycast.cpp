#include "lib/discrete_raycast.h"

#include <stdexcept>

#include <fmt/format.h>

namespace vrv {

void validate(const DiscreteConfig& c, bool grid_field) {
  if (c.oversample < 1 || c.oversample > 65536)
    throw std::invalid_argument(fmt::format("--oversample: must be in [1, 65536], got {}", c.oversample));
  const Strategy st = c.sampling.strategy;
  if (c.centred_oversamples && st != Strategy::step && st != Strategy::vtk && st != Strategy::inviwo)
    throw std::invalid_argument(fmt::format(
        "--centred-oversamples: needs a strategy whose first sample is at least half a step inside "
        "(step, vtk or inviwo), not {}", strategy_name(st)));
  if (c.correction != Correction::none && c.rule != SegmentRule::alpha)
    throw std::invalid_argument(fmt::format(
        "--correction: only the alpha rule composites opacities (method is {})", segment_rule_name(c.rule)));
  if (c.termination && !(*c.termination > 0 && *c.termination <= 1))
    throw std::invalid_argument("--termination: must be in (0, 1]");
  if (c.skip_below && !(*c.skip_below >= 0 && *c.skip_below < 1))
    throw std::invalid_argument("--skip: must be in [0, 1)");
  if (c.termination && c.compositing == Compositing::back_to_front)
    throw std::invalid_argument("--termination: early termination needs front-to-back compositing");
  if (c.classification == Classification::pre && !grid_field)
    throw std::invalid_argument("--classification: pre-classification needs a grid field");
}

DiscreteResult discrete_raycast(const Scene& scene, const Ray& ray, const DiscreteConfig& config) {
  return visit_field(scene, [&](const auto& field) {
    const DiscreteRaycaster raycaster(field, scene.box, scene.transfer, scene.background, config);
    return raycaster.cast(ray);
  });
}

}  // namespace vrv
