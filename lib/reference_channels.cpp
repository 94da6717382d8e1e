#include "lib/reference_channels.h"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

namespace vrv {

std::vector<ReferenceChannel> colour_channels(const Scene& scene, bool over_nothing) {
  const auto background = [&](double b) { return over_nothing ? 0.0 : b; };
  std::vector<ReferenceChannel> channels;
  if (scene.color)
    for (int c = 0; c < 3; ++c) channels.push_back({&scene.color->transfer[c], background(scene.color->background[c])});
  else
    channels.push_back({&scene.transfer, background(scene.background)});
  return channels;
}

ImageChannels::ImageChannels(const Scene& scene, bool alpha) : channels_(colour_channels(scene, alpha)) {
  // With alpha the image is over nothing: premultiplied colour, composited later as C + I0 (1 - A).
  if (!alpha) return;
  alpha_ = std::make_unique<TransferFunction>(channels_.front().transfer->without_emission());
  channels_.push_back({alpha_.get(), 1.0});
}

bool ChannelsReferenceResult::tolerance_met() const {
  const auto all = channels();
  return std::all_of(all.begin(), all.end(), [](const ReferenceResult& r) { return r.tolerance_met; });
}

namespace detail {

void require_channel_count(std::size_t channels) {
  if (channels == 0 || channels > kMaxChannels)
    throw std::invalid_argument(fmt::format("integrate_channels_reference: {} channels, at most {} (R, G, B and alpha)",
                                            channels, kMaxChannels));
}

}  // namespace detail

ChannelsReferenceResult integrate_color_reference(const Scene& scene, const Ray& ray, const ReferenceOptions& options) {
  if (!scene.color) throw std::invalid_argument("integrate_color_reference: the scene is grey (one channel)");
  return visit_field(scene, [&](const auto& field) {
    return integrate_color_reference(field, scene.box, *scene.color, ray, options,
                                     scene.shading_or_null());
  });
}

}  // namespace vrv
