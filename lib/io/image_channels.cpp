#include "lib/io/image_channels.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "lib/io/error_line.h"
#include "lib/io/image_module.h"
#include "lib/io/npy.h"

namespace vrv {
namespace {

namespace fs = std::filesystem;

constexpr int kMaxSide = 1 << 16;
constexpr std::int64_t kMaxPixels = std::int64_t{1} << 28;

// One ulp of a floating type with `mantissa` stored bits at the magnitude `largest`.
double ulp_at(double largest, int mantissa) {
  if (!(largest > 0) || !std::isfinite(largest)) return 0;
  return std::ldexp(1.0, std::ilogb(largest) - mantissa);
}

// The quantum of ChannelImage for a stored pixel type (the image module's names); NaN for a type
// it does not know.
double quantum_or_nan(const std::string& type, double largest) {
  if (type == "uint8") return 1.0 / 255;
  if (type == "uint16") return 1.0 / 65535;
  if (type == "uint" || type == "uint32") return 1.0 / 4294967295.0;
  if (type == "half") return ulp_at(largest, 10);
  if (type == "float") return ulp_at(largest, 23);
  if (type == "double") return ulp_at(largest, 52);
  return std::numeric_limits<double>::quiet_NaN();
}

double quantum_of(const fs::path& path, const std::string& type, double largest) {
  const double q = quantum_or_nan(type, largest);
  if (std::isnan(q)) throw_file_error(path, fmt::format("pixel type {} is not supported", type));
  return q;
}

double largest_finite(const std::vector<double>& values) {
  double largest = 0;
  for (const double v : values)
    if (std::isfinite(v)) largest = std::max(largest, std::abs(v));
  return largest;
}

// A renderer's numpy array saved with numpy.save: read by lib/io/npy.h (OpenImageIO does not).
ChannelImage read_npy_image(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw_file_error(path, "cannot read: no such file");
  return channel_image(read_npy(path), path.string());  // read_npy's errors are "<path>: <reason>" already
}

}  // namespace

ChannelImage::ChannelImage(ImageF64 pixels, std::vector<std::string> channel_names_given)
    : ImageF64(std::move(pixels)), names(std::move(channel_names_given)) {
  if (names.empty()) names = channel_names(channels);
  if (static_cast<int>(names.size()) != channels)
    throw std::invalid_argument(fmt::format("ChannelImage: {} names for {} channels", names.size(), channels));
  for (int c = 0; c < channels && alpha < 0; ++c)
    if (names[c] == "A" || names[c] == "a" || names[c] == "alpha") alpha = c;
  if (alpha < 0 && (channels == 2 || channels == 4)) alpha = channels - 1;
}

ChannelImage channel_image(const NpyArray& a, const std::string& name) {
  const fs::path path(name);
  if (a.shape.size() != 2 && a.shape.size() != 3)
    throw_file_error(path, fmt::format("an array of {} dimensions (expected (height, width) or (height, width, channels))",
                           a.shape.size()));
  const std::size_t h = a.shape[0], w = a.shape[1], nc = a.shape.size() == 3 ? a.shape[2] : 1;
  if (h == 0 || w == 0 || h > kMaxSide || w > kMaxSide || static_cast<std::int64_t>(h * w) > kMaxPixels)
    throw_file_error(path, fmt::format("{} x {} pixels (1 to {} on a side, at most {} in all)", w, h, kMaxSide, kMaxPixels));
  if (nc < 1 || nc > 4) throw_file_error(path, fmt::format("{} channels (1 to 4: grey, grey+alpha, RGB or RGBA)", nc));
  ChannelImage img(ImageF64(static_cast<int>(w), static_cast<int>(h), a.values, static_cast<int>(nc)));
  img.pixel_type = a.dtype == "<f4" ? "float" : "double";
  img.quantum = quantum_of(path, img.pixel_type, largest_finite(img.pixels));
  return img;
}

double stored_quantum(const std::string& pixel_type, double largest) {
  const double q = quantum_or_nan(pixel_type, largest);
  if (std::isnan(q))
    throw std::invalid_argument(fmt::format("stored_quantum: pixel type {} is not supported", pixel_type));
  return q;
}

ChannelImage read_channel_image(const fs::path& path) {
  if (path.extension() == ".npy") return read_npy_image(path);
  image_module::ReadRequest request;
  request.type = image_module::PixelType::float64;
  request.max_channels = 4;
  request.max_side = kMaxSide;
  request.max_pixels = kMaxPixels;
  request.keep_straight_alpha = true;
  const image_module::ReadResult read = image_module::read_file(path, request);
  const int nc = read.channels;
  std::vector<std::string> names = read.channel_names;
  names.resize(nc);
  for (int c = 0; c < nc; ++c)
    if (names[c].empty()) names[c] = channel_names(nc)[c];
  ChannelImage img(ImageF64(read.width, read.height, read.doubles, nc), std::move(names));
  if (read.alpha_channel >= 0) img.alpha = read.alpha_channel;
  img.straight_alpha = read.straight_alpha;
  img.pixel_type = read.pixel_type;
  img.quantum = quantum_of(path, img.pixel_type, largest_finite(img.pixels));
  return img;
}

double effective_quantum(const ChannelImage& image) {
  for (const double steps : {255.0, 65535.0}) {
    if (image.quantum >= 1 / steps * 0.999) return image.quantum;  // already as coarse
    std::vector<double> distinct;
    bool on_grid = true;
    for (const double v : image.pixels) {
      if (!std::isfinite(v)) continue;
      const double k = v * steps;
      // float32 rounding of k/steps, in units of 1/steps, with room for a conversion or two.
      if (std::abs(k - std::round(k)) > 4e-7 * std::max(1.0, std::abs(k))) {
        on_grid = false;
        break;
      }
      if (distinct.size() < 16 && std::find(distinct.begin(), distinct.end(), std::round(k)) == distinct.end())
        distinct.push_back(std::round(k));
    }
    if (on_grid && distinct.size() >= 16) return 1 / steps;
  }
  return image.quantum;
}

}  // namespace vrv
