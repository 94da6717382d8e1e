#include "lib/verify/channel_order.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace vrv {
namespace {

constexpr std::array<const char*, 3> kColourNames{"R", "G", "B"};

// squared[i][k]: the summed squared error of colour channel i judged as reference channel k.
struct OrderErrors {
  std::array<std::array<double, 3>, 3> squared{};
  long pixels = 0;
  double rms(const std::array<int, 3>& order) const {
    double sum = 0;
    for (int i = 0; i < 3; ++i) sum += squared[i][order[i]];
    return pixels ? std::sqrt(sum / (3.0 * pixels)) : 0.0;
  }
};

OrderErrors order_errors(const ChannelImage& im, const std::array<int, 3>& colour,
                         const std::vector<ReferenceImage>& refs, const ColorChannels& color, AlphaMode alpha) {
  OrderErrors e;
  const std::size_t n = refs.front().pixel_count();
  for (std::size_t p = 0; p < n; ++p) {
    std::array<std::array<double, 3>, 3> d{};
    bool finite = true;
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) {
        d[i][k] = comparable(im, colour[i], p, color.background[k], alpha) - refs[k].pixels[p];
        finite = finite && std::isfinite(d[i][k]);
      }
    if (!finite) continue;  // NaN pixels are counted in the channel reports, not here
    ++e.pixels;
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) e.squared[i][k] += d[i][k] * d[i][k];
  }
  return e;
}

std::vector<std::string> names_in(const std::array<int, 3>& order) {
  std::vector<std::string> names;
  for (int k : order) names.emplace_back(kColourNames[k]);
  return names;
}

}  // namespace

std::optional<Fault> swapped_channels(const ImageWithStep& image, const std::vector<int>& truth,
                                      const std::vector<ReferenceImage>& refs, const ColorChannels& color,
                                      AlphaMode alpha) {
  const ChannelImage& im = image.image;
  std::array<int, 3> colour{}, given{};
  int found = 0;
  for (int c = 0; c < im.channels && found < 3; ++c)
    if (c != im.alpha) colour[found] = c, given[found] = truth[c], ++found;
  if (found < 3 || refs.size() != 3) return std::nullopt;
  const OrderErrors errors = order_errors(im, colour, refs, color, alpha);
  std::array<int, 3> order{0, 1, 2}, best = given;
  do
    if (errors.rms(order) < errors.rms(best)) best = order;
  while (std::next_permutation(order.begin(), order.end()));
  const double as_given = errors.rms(given), in_best = errors.rms(best);
  const double floor = effective_quantum(im) / std::sqrt(12.0);
  if (best == given || !(4 * in_best < as_given) || !(as_given > 2 * floor)) return std::nullopt;
  std::vector<std::string> image_names;
  for (int c : colour) image_names.push_back(im.names[c]);
  return Fault{FaultKind::swapped_channels,
               fmt::format("{}: its channels ({}) match the reference's ({}) with RMS error {:.3g}, against "
                           "{:.3g} as read ({}): the colour channels are in another order",
                           image.name, fmt::join(image_names, ", "), fmt::join(names_in(best), ", "), in_best,
                           as_given, fmt::join(names_in(given), ", ")),
               fmt::format("writes the reference's ({}) as ({})", fmt::join(names_in(best), ", "),
                           fmt::join(names_in(given), ", "))};
}

}  // namespace vrv
