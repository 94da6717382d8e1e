#include "lib/verify/verify_inputs.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <string_view>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "lib/option_error.h"
#include "lib/reference_integrator.h"
#include "lib/transfer_table.h"

namespace vrv {
namespace {

void check_image(const ImageWithStep& im, const std::vector<ImageWithStep>& images, bool allow_nan) {
  const ChannelImage& first = images.front().image;
  if (!(im.step > 0) || !std::isfinite(im.step))
    throw VerifyInputError(fmt::format("{}: step {} must be positive and finite", im.name, im.step));
  if (im.image.width != first.width || im.image.height != first.height)
    throw VerifyInputError(fmt::format("{}: size {} x {} differs from {}'s {} x {}", im.name,
                                       im.image.width, im.image.height, images.front().name,
                                       first.width, first.height));
  if (im.image.channels != first.channels)
    throw VerifyInputError(fmt::format("{}: {} channels, {} has {}", im.name, im.image.channels,
                                       images.front().name, first.channels));
  for (const ImageWithStep& other : images)
    if (&other != &im && other.step == im.step)
      throw VerifyInputError(fmt::format("{}: step {} repeats {}'s", im.name, im.step, other.name));
  if (allow_nan) return;
  for (int c = 0; c < im.image.channels; ++c)  // channel by channel: the first NaN of the first channel
    for (std::size_t i = 0; i < im.image.pixel_count(); ++i)
      if (!std::isfinite(im.image.value(i, c)))
        throw VerifyInputError(fmt::format("{}: pixel ({}, {}) channel {} is {}", im.name,
                                           i % im.image.width, i / im.image.width,
                                           im.image.names[c], im.image.value(i, c)));
}

void check_options(const VerifyOptions& opt) {
  if (!(opt.threshold >= 0)) throw OptionError(Option::threshold, "must be >= 0");
  check_tolerance(opt.reference_tol);
  if (opt.expected_order && !(*opt.expected_order > 0 && std::isfinite(*opt.expected_order)))
    throw OptionError(Option::expected_order,
                      fmt::format("must be a positive finite order, got {}", *opt.expected_order));
  for (int n : opt.table_sizes)
    if (n < 2 || n > kMaxTableSize)
      throw std::invalid_argument(fmt::format("table_sizes: {} is not in [2, {}]", n, kMaxTableSize));
}

}  // namespace

void check_inputs(const std::vector<ImageWithStep>& images, const VerifyOptions& opt) {
  if (images.empty()) throw VerifyInputError("no images to verify");
  for (const ImageWithStep& im : images) check_image(im, images, opt.allow_nan);
  check_options(opt);
  // The channels agree in number (check_image), so the first image says whether there is alpha.
  if (opt.alpha != AlphaMode::as_stored && images.front().image.alpha < 0)
    throw OptionError(Option::alpha, fmt::format("{}: the images have no alpha channel, so there is nothing to take "
                                                 "{}; leave the option out",
                                                 alpha_mode_name(opt.alpha), alpha_mode_name(opt.alpha)));
}

std::vector<const ImageWithStep*> sorted_by_step(const std::vector<ImageWithStep>& images) {
  std::vector<const ImageWithStep*> sorted;
  for (const ImageWithStep& im : images) sorted.push_back(&im);
  std::stable_sort(sorted.begin(), sorted.end(), [](auto* a, auto* b) { return a->step > b->step; });
  return sorted;
}

double comparable(const ChannelImage& im, int c, std::size_t i, double background, AlphaMode mode) {
  const double v = im.value(i, c);
  if (im.alpha < 0 || c == im.alpha) return v;
  const double a = im.value(i, im.alpha);
  const bool straight = mode == AlphaMode::straight || (mode == AlphaMode::as_stored && im.straight_alpha);
  return (straight ? v * a : v) + background * (1 - a);
}

namespace {

// 0, 1, 2 for a red, green or blue channel name ("R", "green", "rgba.B"); -1 otherwise.
int colour_of_name(const std::string& name) {
  const std::size_t dot = name.find_last_of('.');
  std::string last = name.substr(dot == std::string::npos ? 0 : dot + 1);
  std::transform(last.begin(), last.end(), last.begin(), [](unsigned char ch) { return std::tolower(ch); });
  constexpr std::array<std::array<std::string_view, 2>, 3> kNames{{{"r", "red"}, {"g", "green"}, {"b", "blue"}}};
  for (int k = 0; k < 3; ++k)
    if (last == kNames[k][0] || last == kNames[k][1]) return k;
  return -1;
}

}  // namespace

std::vector<int> reference_channels(const ImageWithStep& im, int scene_channels) {
  const ChannelImage& image = im.image;
  std::vector<int> truth(image.channels, 0);
  if (scene_channels == 1) return truth;
  std::vector<int> colour;
  for (int c = 0; c < image.channels; ++c)
    if (c != image.alpha) colour.push_back(c);
  if (colour.size() != 3)
    throw VerifyInputError(fmt::format("{}: {} colour channel(s) ({}), but the scene is RGB: give an image with "
                                       "three colour channels (R, G, B)", im.name, colour.size(),
                                       fmt::join(image.names, ", ")));
  // By name when the three name three different colours, else in order.
  std::array<int, 3> by_name{};
  std::array<bool, 3> seen{};
  bool named = true;
  for (int k = 0; k < 3; ++k) {
    by_name[k] = colour_of_name(image.names[colour[k]]);
    named = named && by_name[k] >= 0 && !seen[by_name[k]];
    if (by_name[k] >= 0) seen[by_name[k]] = true;
  }
  for (int k = 0; k < 3; ++k) truth[colour[k]] = named ? by_name[k] : k;
  return truth;
}

int first_colour_channel(const ChannelImage& image) {
  const int nc = image.channels;
  int colour = 0;
  while (colour < nc && colour == image.alpha) ++colour;
  return colour;
}

}  // namespace vrv
