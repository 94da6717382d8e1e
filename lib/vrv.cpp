#include "lib/vrv.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <type_traits>

#include <fmt/format.h>

#include "lib/image_loop.h"
#include "lib/option_error.h"
#include "lib/reference_pixels.h"
#include "lib/util/parallel.h"

namespace vrv {

Camera scene_camera(const Scene& scene, std::optional<int> width, std::optional<int> height) {
  Camera camera = scene.camera ? *scene.camera : default_camera(scene.box);
  if (width) camera.width = *width;
  if (height) camera.height = *height;
  try {
    validate(camera);
  } catch (const CameraError& e) {
    if (e.field() == "width" && width) throw OptionError(Option::width, e.reason());
    if (e.field() == "height" && height) throw OptionError(Option::height, e.reason());
    // Without a [camera] the camera is made from the box: a box so far out or so large that it
    // cannot be framed in double is the box's fault, not a camera table's the scene does not have.
    if (!scene.camera)
      throw std::invalid_argument(fmt::format(
          "the scene's box [{}, {}, {}] to [{}, {}, {}] is too far out or too large for the default camera in "
          "double ({}); give the scene a [camera]", scene.box.min.x(), scene.box.min.y(), scene.box.min.z(), scene.box.max.x(),
          scene.box.max.y(), scene.box.max.z(), e.what()));
    throw std::invalid_argument(fmt::format("[camera]: {}", e.what()));
  }
  return camera;
}

std::vector<Ray> camera_rays(const Camera& camera) {
  validate(camera);
  return image_loop(camera, [](const Ray& ray) { return ray; });
}

void reference_values(const Scene& scene, std::span<const Ray> rays,
                      const ReferenceOptions& options, std::span<ReferenceResult> out) {
  require_grey(scene, "scene", "reference_values");
  if (out.size() != rays.size())
    throw std::invalid_argument(
        fmt::format("reference_values: {} results for {} rays", out.size(), rays.size()));
  validate(options);
  visit_field(scene, [&](const auto& field) {
    parallel_for_index(static_cast<long>(rays.size()), [&](long i) {
      out[i] = integrate_reference(field, scene.box, scene.transfer, scene.background, rays[i], options,
                                   scene.shading_or_null());
    });
  });
}

std::vector<ReferenceResult> reference_values(const Scene& scene, std::span<const Ray> rays,
                                              const ReferenceOptions& options) {
  std::vector<ReferenceResult> out(rays.size());
  reference_values(scene, rays, options, out);
  return out;
}

std::vector<ChannelsReferenceResult> color_reference_values(const Scene& scene, std::span<const Ray> rays,
                                                            const ReferenceOptions& options) {
  if (!scene.color) throw std::invalid_argument("color_reference_values: the scene is grey (use reference_values)");
  return channel_reference_values(scene, rays, options, false);
}

std::vector<ChannelsReferenceResult> channel_reference_values(const Scene& scene, std::span<const Ray> rays,
                                                              const ReferenceOptions& options, bool alpha) {
  validate(options);
  const ImageChannels channels(scene, alpha);
  std::vector<ChannelsReferenceResult> out(rays.size());
  visit_field(scene, [&](const auto& field) {
    parallel_for_index(static_cast<long>(rays.size()), [&](long i) {
      out[i] = integrate_image_channels(field, scene.box, channels, rays[i], options, scene.shading_or_null());
    });
  });
  return out;
}

std::vector<ProjectionResult> projection_values(const Scene& scene, std::span<const Ray> rays, ProjectionMode mode,
                                                const ProjectionOptions& options) {
  require_grey(scene, "scene", "projection_values");
  validate(options);
  std::vector<ProjectionResult> out(rays.size());
  visit_field(scene, [&](const auto& field) {
    parallel_for_index(static_cast<long>(rays.size()), [&](long i) {
      out[i] = projection_reference(field, scene.box, scene.transfer, rays[i], mode, options);
    });
  });
  return out;
}

std::vector<DiscreteProjectionResult> discrete_projection_values(const Scene& scene, std::span<const Ray> rays,
                                                                 const DiscreteProjectionConfig& config) {
  require_grey(scene, "scene", "discrete_projection_values");
  std::vector<DiscreteProjectionResult> out(rays.size());
  visit_field(scene, [&](const auto& field) {
    parallel_for_index(static_cast<long>(rays.size()), [&](long i) {
      out[i] = discrete_projection(field, scene.box, scene.transfer, rays[i], config);
    });
  });
  return out;
}

std::vector<DiscreteResult> discrete_values(const Scene& scene, std::span<const Ray> rays,
                                            const DiscreteConfig& config) {
  require_grey(scene, "scene", "discrete_values (discrete_channel_values casts every channel)");
  validate(config, std::holds_alternative<GridField>(scene.field));
  std::vector<DiscreteResult> out(rays.size());
  visit_field(scene, [&](const auto& field) {
    using F = std::decay_t<decltype(field)>;
    const DiscreteRaycaster<F> caster = scene_raycaster(field, scene, config);
    parallel_for_index(static_cast<long>(rays.size()), [&](long i) { out[i] = caster.cast(rays[i]); });
  });
  return out;
}

ValueImage render_reference_image(const Scene& scene, const Camera& camera, const ReferenceOptions& options) {
  require_grey(scene, "scene", "render_reference_image");
  validate(camera);
  validate(options);
  const long pixels = pixel_count(camera);
  ValueImage image(camera.width, camera.height, std::vector<double>(static_cast<std::size_t>(pixels)));
  std::vector<long> evaluations(image.pixels.size());
  std::vector<double> estimates(image.pixels.size());
  reference_pixels(scene, camera, options, [&](long i, const ReferenceResult& r) {
    image.pixels[i] = r.value, evaluations[i] = r.evaluations, estimates[i] = r.error_estimate;
  });
  // The sums in pixel order: the same for any thread count.
  for (long i = 0; i < pixels; ++i) {
    image.work += evaluations[i];
    image.max_error_estimate = std::max(image.max_error_estimate, estimates[i]);
  }
  return image;
}

ValueImage render_discrete_image(const Scene& scene, const Camera& camera, const DiscreteConfig& config) {
  require_grey(scene, "scene", "render_discrete_image");
  validate(camera);
  validate(config, std::holds_alternative<GridField>(scene.field));
  const std::vector<DiscreteResult> results = visit_field(scene, [&](const auto& field) {
    using F = std::decay_t<decltype(field)>;
    const DiscreteRaycaster<F> caster = scene_raycaster(field, scene, config);
    return image_loop(camera, [&](const Ray& ray) { return caster.cast(ray); });
  });
  ValueImage image(camera.width, camera.height, std::vector<double>(results.size()));
  for (std::size_t i = 0; i < results.size(); ++i) {
    image.pixels[i] = results[i].value;
    image.work += results[i].samples;
  }
  return image;
}

namespace {

std::string image_label(std::size_t index, double step) { return fmt::format("image {} (step {:g})", index, step); }

void check_step_count(std::size_t steps, std::size_t images) {
  if (images != steps)
    throw VerifyInputError(fmt::format("--steps: {} steps for {} images (one step per image, in the same order)",
                                       steps, images));
}

// A computed image as verify_images reads a file: one channel "Y" in double, no quantisation.
ChannelImage channels_of(const ValueImage& image, const std::string& name) {
  if (image.channels != 1)
    throw VerifyInputError(fmt::format("{}: {} channels (a ValueImage is grey: give ChannelImages for more)", name,
                                       image.channels));
  if (image.width <= 0 || image.height <= 0 || image.pixels.size() != image.pixel_count())
    throw VerifyInputError(fmt::format("{}: {} values for {} x {} pixels", name, image.pixels.size(),
                                       image.width, image.height));
  ChannelImage channels(image);
  channels.pixel_type = "double";  // quantum 0: in memory, not rounded to a file's type
  return channels;
}

}  // namespace

VerifyReport verify(const Scene& scene, const std::vector<ChannelImage>& images,
                    const std::vector<double>& steps, const VerifyOptions& options) {
  check_step_count(steps.size(), images.size());
  std::vector<ImageWithStep> inputs;
  for (std::size_t i = 0; i < images.size(); ++i) inputs.push_back({image_label(i, steps[i]), steps[i], images[i]});
  return verify_images(scene, inputs, options);
}

VerifyReport verify(const Scene& scene, const std::vector<ValueImage>& images,
                    const std::vector<double>& steps, const VerifyOptions& options) {
  check_step_count(steps.size(), images.size());
  std::vector<ChannelImage> channels;
  for (std::size_t i = 0; i < images.size(); ++i) channels.push_back(channels_of(images[i], image_label(i, steps[i])));
  return verify(scene, channels, steps, options);
}

VerifyReport verify(const Scene& scene, const std::vector<double>& steps, const Renderer& render,
                    const VerifyOptions& options) {
  VerifyOptions with_camera = options;
  if (!with_camera.camera) with_camera.camera = scene_camera(scene);
  const Camera& camera = *with_camera.camera;
  std::vector<ValueImage> images;
  for (double step : steps) {
    images.push_back(render(camera, step));
    const ValueImage& im = images.back();
    if (im.width != camera.width || im.height != camera.height)
      throw VerifyInputError(fmt::format("renderer: its image for step {:g} is {} x {}, the camera's {} x {}",
                                         step, im.width, im.height, camera.width, camera.height));
  }
  return verify(scene, images, steps, with_camera);
}

bool passes(const VerifyReport& report, const BoundSet& bounds) {
  return report.pass && worst(evaluate_bounds("verify", report, bounds)) < BoundVerdict::fail;
}

}  // namespace vrv
