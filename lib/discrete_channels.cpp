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

std::vector<std::vector<double>> discrete_channel_planes(const Scene& scene, const Camera& camera,
                                                         const DiscreteConfig& config, bool alpha) {
  validate(camera);
  validate(config, std::holds_alternative<GridField>(scene.field));
  const long pixels = pixel_count(camera);
  const int channels = scene.channel_count() + (alpha ? 1 : 0);
  std::vector<std::vector<double>> planes(channels, std::vector<double>(static_cast<std::size_t>(pixels)));
  discrete_channel_pixels(scene, camera, config, [&](long i, const ChannelsDiscreteResult& r) {
    for (std::size_t c = 0; c < planes.size(); ++c) planes[c][i] = r.value[c];
  }, {}, {}, alpha);
  return planes;
}

}  // namespace vrv
