#include "lib/discrete_channels.h"

#include <variant>

#include "lib/util/parallel.h"

namespace vrv {

std::vector<ChannelsDiscreteResult> discrete_channel_values(const Scene& scene, std::span<const Ray> rays,
                                                            const DiscreteConfig& config) {
  validate(config, std::holds_alternative<GridField>(scene.field));
  std::vector<ChannelsDiscreteResult> out(rays.size());
  visit_field(scene, [&](const auto& field) {
    const DiscreteChannelCaster caster(field, scene, config);
    parallel_for_index(static_cast<long>(rays.size()), [&](long i) { out[i] = caster.cast(rays[i]); });
  });
  return out;
}

ImageF64 discrete_channel_image(const Scene& scene, const Camera& camera, const DiscreteConfig& config,
                                bool alpha) {
  validate(camera);
  validate(config, std::holds_alternative<GridField>(scene.field));
  ImageF64 image(camera.width, camera.height, 0.0, scene.channel_count() + (alpha ? 1 : 0));
  discrete_channel_pixels(scene, camera, config, [&](long i, const ChannelsDiscreteResult& r) {
    for (int c = 0; c < image.channels; ++c) image.value(i, c) = r.value[c];
  }, {}, {}, alpha);
  return image;
}

}  // namespace vrv
