#pragma once
// The reference of several channels under the one optical depth they share, from one set of
// panels of the field: an RGB scene's three colours, and alpha (A = 1 - e^-Phi) where asked.
//
// One RayAccumulator carries the channels in lockstep (lib/ray_accumulator.h): the panels, cuts,
// depth and routes are shared, each channel keeps its own value and honest estimate, and a piece
// is split until every channel still integrating accepts it.  Channels that all have a grey
// scene's transfer function and background get the grey scene's value bit for bit.
#include <array>
#include <memory>
#include <span>
#include <vector>

#include "lib/reference_integrator.h"
#include "lib/scene.h"

namespace vrv {

// A scene's colour channels: one grey, or red, green and blue.  `over_nothing` gives each a
// background of 0 (premultiplied colour, as an image with alpha has: see ImageChannels).
std::vector<ReferenceChannel> colour_channels(const Scene& scene, bool over_nothing);

// The channels of a scene's image: its colour channels (one grey, or red, green and blue) and, with
// `alpha`, one more whose value is the transmittance e^-Phi: the same extinction without emission
// over a background of 1 (so A = 1 - that value, with its estimate).  With alpha the colour is
// rendered over nothing (background 0): premultiplied RGBA, as EXR and compositing expect, whose
// colour over the scene's background I0 is C + I0 (1 - A).  Owns the alpha channel's transfer
// function; the scene must outlive it.
class ImageChannels {
 public:
  ImageChannels(const Scene& scene, bool alpha);
  std::span<const ReferenceChannel> channels() const { return channels_; }
  int count() const { return static_cast<int>(channels_.size()); }
  bool alpha() const { return alpha_ != nullptr; }

 private:
  std::unique_ptr<TransferFunction> alpha_;  // a stable address for channels_
  std::vector<ReferenceChannel> channels_;
};

// The most channels an image has: R, G, B and alpha.
inline constexpr int kMaxChannels = 4;

// The channels' results from one walk per ray (grey or red, green, blue, then alpha where asked).
// Of fixed size, so a pixel of them is a record MPI ranks exchange as bytes (lib/image_loop.h).
struct ChannelsReferenceResult {
  std::array<ReferenceResult, kMaxChannels> channel{};  // the first `count`; each counts the shared evaluations
  int count = 0;
  long evaluations = 0;  // field evaluations for all of them
  std::span<const ReferenceResult> channels() const& { return std::span(channel).first(count); }
  // A span into a temporary would outlive it (a range-for over f().channels() reads freed stack).
  std::span<const ReferenceResult> channels() const&& = delete;
  bool tolerance_met() const;
};

namespace detail {

// Throws std::invalid_argument for no channel, or more than a ChannelsReferenceResult holds.
void require_channel_count(std::size_t channels);

template <int N>
ChannelsReferenceResult channels_result(const std::array<ReferenceResult, N>& results) {
  ChannelsReferenceResult out;
  out.count = N;
  out.evaluations = results[0].evaluations;
  std::copy(results.begin(), results.end(), out.channel.begin());
  return out;
}

// integrate_passes with the accumulator of the channels' count.
template <ScalarField F>
ChannelsReferenceResult integrate_channels_passes(const F& field, const RayFrame& frame,
                                                  std::span<const ReferenceChannel> channels,
                                                  const ReferenceOptions& options, const Shading* shading) {
  switch (channels.size()) {
    case 1: return channels_result<1>(integrate_passes<1>(field, frame, channels.first<1>(), options, shading));
    case 2: return channels_result<2>(integrate_passes<2>(field, frame, channels.first<2>(), options, shading));
    case 3: return channels_result<3>(integrate_passes<3>(field, frame, channels.first<3>(), options, shading));
    default: return channels_result<4>(integrate_passes<4>(field, frame, channels.first<4>(), options, shading));
  }
}

}  // namespace detail

// The grey integrate_reference's contract per channel, with the same walk and retry
// (detail::integrate_passes).
// shading: a factor on every channel's emission (lib/shading.h), or none.
// Throws std::invalid_argument for none or more than kMaxChannels channels, or channels whose
// extinctions differ (require_shared_extinction).
template <ScalarField F>
ChannelsReferenceResult integrate_channels_reference(const F& field, const Box& box,
                                                     std::span<const ReferenceChannel> channels, const Ray& ray,
                                                     const ReferenceOptions& options = {},
                                                     const Shading* shading = nullptr) {
  detail::require_channel_count(channels.size());
  require_shared_extinction(channels);
  const auto frame = clip_in_frame(ray, box);
  if (!frame) {
    ChannelsReferenceResult miss;
    miss.count = static_cast<int>(channels.size());
    for (int c = 0; c < miss.count; ++c) miss.channel[c].value = channels[c].background;
    return miss;
  }
  return detail::integrate_channels_passes(field, *frame, channels, options, shading);
}

// The channels of an image (ImageChannels), alpha as A = 1 - e^-Phi: its channel's transmittance
// turned over, with the same optical depth and the transmittance's estimate plus the rounding of
// the subtraction (half an ulp of A, taken as a whole ulp: where T is tiny its estimate is far
// below an ulp of 1, and that rounding is most of A's error).
template <ScalarField F>
ChannelsReferenceResult integrate_image_channels(const F& field, const Box& box, const ImageChannels& channels,
                                                 const Ray& ray, const ReferenceOptions& options = {},
                                                 const Shading* shading = nullptr) {
  ChannelsReferenceResult r = integrate_channels_reference(field, box, channels.channels(), ray, options, shading);
  if (channels.alpha()) {
    ReferenceResult& a = r.channel[r.count - 1];
    a.value = 1 - a.value;
    a.error_estimate += std::numeric_limits<double>::epsilon() * std::abs(a.value);
    a.tolerance_met = a.tolerance_met && a.error_estimate <= options.tol;
  }
  return r;
}

// An RGB scene's three channels (integrate_channels_reference): red, green, blue.
template <ScalarField F>
ChannelsReferenceResult integrate_color_reference(const F& field, const Box& box, const ColorChannels& color,
                                                  const Ray& ray, const ReferenceOptions& options = {},
                                                  const Shading* shading = nullptr) {
  std::array<ReferenceChannel, 3> channels;
  for (int c = 0; c < 3; ++c) channels[c] = {&color.transfer[c], color.background[c]};
  return integrate_channels_reference(field, box, channels, ray, options, shading);
}

// The scene's field, dispatched to its concrete type.  Throws std::invalid_argument for a grey scene.
ChannelsReferenceResult integrate_color_reference(const Scene& scene, const Ray& ray,
                                                  const ReferenceOptions& options = {});

}  // namespace vrv
