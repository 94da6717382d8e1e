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

int emitting_channels(std::span<const ReferenceChannel> channels) {
  return static_cast<int>(std::count_if(channels.begin(), channels.end(),
                                        [](const ReferenceChannel& c) { return c.transfer->max_emission() > 0; }));
}

void require_channel_count(std::size_t channels) {
  if (channels > kMaxChannels)
    throw std::invalid_argument(fmt::format("integrate_channels_reference: {} channels, at most {} (R, G, B and alpha)",
                                            channels, kMaxChannels));
}

ChannelAccumulators::ChannelAccumulators(std::span<const ReferenceChannel> channels, const ReferenceOptions& options,
                                         Interval iv, double position_error, const EmissionWeight* weight) {
  accumulators_.reserve(channels.size());
  for (const ReferenceChannel& c : channels)
    accumulators_.emplace_back(*c.transfer, c.background, options, iv, position_error, weight);
  if (accumulators_.size() < 2) return;
  // Room for every piece a panel keeps, once per ray: grown from a few, its 4 KB entries were
  // value-initialised and moved at every doubling, on every ray (a shaded RGB grid ray took 1.7x
  // as long).
  depths_.reserve(SpectralDepthShare::kMaxPieces);
  for (RayAccumulator& a : accumulators_) a.share_depth(&depths_);
}

double ChannelAccumulators::field_tolerance() const {
  double tol = std::numeric_limits<double>::infinity();
  for (const RayAccumulator& a : accumulators_)
    if (!a.stopped()) tol = std::min(tol, a.field_tolerance());
  return tol;
}

bool ChannelAccumulators::jumps_located(const RayPanel& panel) {
  bool located = true;
  for (RayAccumulator& a : accumulators_)
    if (!a.stopped()) located = a.jumps_located(panel) && located;
  return located;
}

void ChannelAccumulators::consume(const RayPanel& panel) {
  depths_.clear();  // keyed by piece: another panel's would be read as this one's
  for (RayAccumulator& a : accumulators_) a.consume(panel);
}

bool ChannelAccumulators::stopped() const {
  return std::all_of(accumulators_.begin(), accumulators_.end(), [](const RayAccumulator& a) { return a.stopped(); });
}

void ChannelAccumulators::give_up(double t) {
  for (RayAccumulator& a : accumulators_) a.give_up(t);
}

void ChannelAccumulators::note_cap() {
  for (RayAccumulator& a : accumulators_)
    if (!a.stopped()) a.note_cap();
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
