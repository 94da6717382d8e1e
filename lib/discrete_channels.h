#pragma once
// The discrete raycast of every channel of a scene: a grey scene's one, an RGB scene's three, each
// cast alone with its channel's transfer function and background.  The channels share the
// extinction, so each composites the same opacities with its own colour; this is how vrv render,
// vrv gate, vrv ray and the Python module cast a scene, from this one place.
#include <array>
#include <span>
#include <vector>

#include "lib/discrete_raycast.h"
#include "lib/image_loop.h"
#include "lib/io/image_io.h"
#include "lib/reference_channels.h"
#include "lib/scene.h"

namespace vrv {

// A ray's value in each channel (the first ImageChannels::count() entries: the scene's channels,
// then alpha when asked) and the samples taken over all of them.
struct ChannelsDiscreteResult {
  std::array<double, 4> value{};
  long samples = 0;
};

// One DiscreteRaycaster per colour channel of the scene (colour_channels: grey or RGB); with
// alpha, A = 1 - the first channel's transmittance (the channels composite the same opacities, so
// it is the same in each, and bitwise what a cast of no emission over a background of 1 gives).
// The scene and field must outlive it.
template <class F>
class DiscreteChannelCaster {
 public:
  DiscreteChannelCaster(const F& field, const Scene& scene, const DiscreteConfig& config, bool alpha = false)
      : alpha_(alpha) {
    const std::vector<ReferenceChannel> colour = colour_channels(scene, alpha);
    casters_.reserve(colour.size());
    for (const ReferenceChannel& c : colour)
      casters_.emplace_back(field, scene.box, *c.transfer, c.background, config, scene.shading_or_null(), scene.dims);
  }

  ChannelsDiscreteResult cast(const Ray& ray) const {
    ChannelsDiscreteResult r;
    double transmittance = 1;
    for (std::size_t c = 0; c < casters_.size(); ++c) {
      const DiscreteResult v = casters_[c].cast(ray);
      r.value[c] = v.value;
      r.samples += v.samples;
      if (c == 0) transmittance = v.transmittance;
    }
    if (alpha_) r.value[casters_.size()] = 1 - transmittance;
    return r;
  }

 private:
  bool alpha_;
  std::vector<DiscreteRaycaster<F>> casters_;
};

// put(position, ChannelsDiscreteResult) for each pixel of the camera (or of `subset`), through the
// image loop (lib/image_loop.h).  `config` is taken as validated.
// With `alpha`, each pixel's last channel is A (DiscreteChannelCaster).
template <class Put>
void discrete_channel_pixels(const Scene& scene, const Camera& camera, const DiscreteConfig& config, Put&& put,
                             const ImageLoopHooks& hooks = {}, std::span<const long> subset = {},
                             bool alpha = false) {
  visit_field(scene, [&](const auto& field) {
    const DiscreteChannelCaster caster(field, scene, config, alpha);
    image_loop_into(camera, subset, [&](const Ray& ray) { return caster.cast(ray); }, put, hooks);
  });
}

// The same along rays, in parallel, one slot per ray.  Throws std::invalid_argument (naming the
// option) when validate(config, grid field) refuses the configuration.
std::vector<ChannelsDiscreteResult> discrete_channel_values(const Scene& scene, std::span<const Ray> rays,
                                                            const DiscreteConfig& config);

// A camera's image, every channel of a pixel together (with `alpha`, A last); validates the
// camera and the configuration as discrete_channel_values does.
ImageF64 discrete_channel_image(const Scene& scene, const Camera& camera, const DiscreteConfig& config,
                                bool alpha = false);

}  // namespace vrv
