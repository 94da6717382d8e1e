#include "lib/vrv.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <type_traits>

#include <fmt/format.h>

#include "lib/util/parallel.h"

namespace vrv {

Camera scene_camera(const Scene& scene, std::optional<int> width, std::optional<int> height) {
  Camera camera = scene.camera ? *scene.camera : default_camera(scene.box);
  if (width) camera.width = *width;
  if (height) camera.height = *height;
  try {
    validate(camera);
  } catch (const CameraError& e) {
    if (e.field() == "width" && width) throw std::invalid_argument("--width: " + e.reason());
    if (e.field() == "height" && height) throw std::invalid_argument("--height: " + e.reason());
    throw std::invalid_argument(fmt::format("[camera]: {}", e.what()));
  }
  return camera;
}

void validate(const ReferenceOptions& options) {
  if (!(options.tol > 0) || !std::isfinite(options.tol))
    throw std::invalid_argument(
        fmt::format("--tol: must be a positive finite number, got {}", options.tol));
}

std::vector<Ray> camera_rays(const Camera& camera) {
  validate(camera);
  const long pixels = static_cast<long>(camera.width) * camera.height;
  std::vector<Ray> rays(static_cast<std::size_t>(pixels));
  parallel_for_index(pixels, [&](long i) {
    rays[i] = camera.ray(static_cast<int>(i % camera.width), static_cast<int>(i / camera.width));
  });
  return rays;
}

void reference_values(const Scene& scene, std::span<const Ray> rays,
                      const ReferenceOptions& options, std::span<ReferenceResult> out) {
  if (out.size() != rays.size())
    throw std::invalid_argument(
        fmt::format("reference_values: {} results for {} rays", out.size(), rays.size()));
  validate(options);
  visit_field(scene, [&](const auto& field) {
    parallel_for_index(static_cast<long>(rays.size()), [&](long i) {
      out[i] = integrate_reference(field, scene.box, scene.transfer, scene.background, rays[i], options);
    });
  });
}

std::vector<ReferenceResult> reference_values(const Scene& scene, std::span<const Ray> rays,
                                              const ReferenceOptions& options) {
  std::vector<ReferenceResult> out(rays.size());
  reference_values(scene, rays, options, out);
  return out;
}

std::vector<DiscreteResult> discrete_values(const Scene& scene, std::span<const Ray> rays,
                                            const DiscreteConfig& config) {
  validate(config, std::holds_alternative<GridField>(scene.field));
  std::vector<DiscreteResult> out(rays.size());
  visit_field(scene, [&](const auto& field) {
    using F = std::decay_t<decltype(field)>;
    const DiscreteRaycaster<F> caster(field, scene.box, scene.transfer, scene.background, config);
    parallel_for_index(static_cast<long>(rays.size()), [&](long i) { out[i] = caster.cast(rays[i]); });
  });
  return out;
}

namespace {

// The per-ray results as an image; the sums run in pixel order (thread-count independent).
template <class Result, class Work, class Estimate>
ValueImage to_image(const Camera& camera, const std::vector<Result>& results, Work work,
                    Estimate estimate) {
  ValueImage image{camera.width, camera.height, std::vector<double>(results.size())};
  for (std::size_t i = 0; i < results.size(); ++i) {
    image.values[i] = results[i].value;
    image.work += work(results[i]);
    image.max_error_estimate = std::max(image.max_error_estimate, estimate(results[i]));
  }
  return image;
}

}  // namespace

ValueImage render_reference_image(const Scene& scene, const Camera& camera, const ReferenceOptions& options) {
  return to_image(camera, reference_values(scene, camera_rays(camera), options),
                  [](const ReferenceResult& r) { return r.evaluations; },
                  [](const ReferenceResult& r) { return r.error_estimate; });
}

ValueImage render_discrete_image(const Scene& scene, const Camera& camera, const DiscreteConfig& config) {
  return to_image(camera, discrete_values(scene, camera_rays(camera), config),
                  [](const DiscreteResult& r) { return r.samples; },
                  [](const DiscreteResult&) { return 0.0; });
}

}  // namespace vrv
