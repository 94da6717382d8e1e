#pragma once
// The reference of an RGB scene: the three channels' emission under the one optical depth they
// share, from one set of panels of the field.
//
// Each channel keeps its own RayAccumulator (its own crossings, bands and error estimate, so each
// channel's promise is the grey integrator's); the panels are fitted once and refined until every
// channel still integrating accepts them, so a field is evaluated once for all three.  A channel
// given the same transfer function as a grey scene gets the grey scene's value bit for bit.
#include <array>
#include <vector>

#include "lib/reference_integrator.h"
#include "lib/scene.h"

namespace vrv {

struct ColorReferenceResult {
  std::array<ReferenceResult, 3> channel;  // red, green, blue; each counts the shared evaluations
  long evaluations = 0;                    // field evaluations for all three
  bool tolerance_met() const {
    return channel[0].tolerance_met && channel[1].tolerance_met && channel[2].tolerance_met;
  }
};

namespace detail {

// The three channels' accumulators behind RayAccumulator's interface, as walk_ray drives it.
class ChannelAccumulators {
 public:
  ChannelAccumulators(const ColorChannels& color, const ReferenceOptions& options, Interval iv,
                      double position_error, const EmissionWeight* weight = nullptr);

  // The tightest of the channels still integrating: a panel good for it is good for all.
  double field_tolerance() const;
  // Every channel still integrating has its jumps located (each one asked: it keeps its bands).
  bool jumps_located(const RayPanel& panel);
  void consume(const RayPanel& panel);
  bool stopped() const;
  void give_up(double t);
  void note_cap();
  double position_error() const { return accumulators_[0].position_error(); }
  ReferenceResult finish(int c) const { return accumulators_[c].finish(); }

 private:
  std::vector<RayAccumulator> accumulators_;
};

// A stretch is empty only where every channel is transparent.
struct AllChannelsTransparent {
  const ColorChannels& color;
  bool transparent_on(double lo, double hi) const {
    for (const TransferFunction& tf : color.transfer)
      if (!tf.transparent_on(lo, hi)) return false;
    return true;
  }
  // Every channel transparent somewhere in [lo, hi] (not necessarily at one value: a gate may say
  // yes where no stretch is empty, never no where one is).
  bool transparent_somewhere(double lo, double hi) const {
    for (const TransferFunction& tf : color.transfer)
      if (!tf.transparent_somewhere(lo, hi)) return false;
    return true;
  }
};

template <ScalarField F>
ColorReferenceResult integrate_color_pass(const F& field, const RayFrame& frame, const ColorChannels& color,
                                          const ReferenceOptions& options, const Shading* shading) {
  const auto weight = shading_on(field, frame, shading);
  ChannelAccumulators acc(color, options, frame.iv, field_change_within(field, frame.position_error),
                          weight.get());
  const long evaluations = walk_ray(field, frame, AllChannelsTransparent{color}, options, acc);
  ColorReferenceResult result;
  result.evaluations = evaluations;
  for (int c = 0; c < 3; ++c) {
    ReferenceResult& r = result.channel[c];
    r = acc.finish(c);
    r.t_entry = frame.t_entry();
    r.t_exit = frame.t_exit();
    r.evaluations = evaluations;
  }
  return result;
}

}  // namespace detail

// The grey integrate_reference's contract per channel, with the same retry: when any channel
// missed its tolerance by a little, all three are integrated once more at the tighter tolerance
// (the panels are shared) and each keeps its smaller estimate.
// shading: a factor on every channel's emission (lib/shading.h), or none.
template <ScalarField F>
ColorReferenceResult integrate_color_reference(const F& field, const Box& box, const ColorChannels& color,
                                               const Ray& ray, const ReferenceOptions& options = {},
                                               const Shading* shading = nullptr) {
  const auto frame = clip_in_frame(ray, box);
  if (!frame) {
    ColorReferenceResult miss;
    for (int c = 0; c < 3; ++c) miss.channel[c].value = color.background[c];
    return miss;
  }
  ColorReferenceResult first = detail::integrate_color_pass(field, *frame, color, options, shading);
  bool retry = false;
  for (const ReferenceResult& r : first.channel) retry = retry || detail::worth_retry(r, options.tol);
  if (!retry) return first;
  const ColorReferenceResult second =
      detail::integrate_color_pass(field, *frame, color, detail::retry_options(options), shading);
  ColorReferenceResult kept;
  kept.evaluations = first.evaluations + second.evaluations;
  for (int c = 0; c < 3; ++c) kept.channel[c] = detail::better_pass(first.channel[c], second.channel[c], options.tol);
  return kept;
}

// The scene's field, dispatched to its concrete type.  Throws std::invalid_argument for a grey scene.
ColorReferenceResult integrate_color_reference(const Scene& scene, const Ray& ray,
                                               const ReferenceOptions& options = {});

}  // namespace vrv
