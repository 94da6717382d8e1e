#include "lib/io/image_channels.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include <fmt/format.h>

#include "lib/io/image_module.h"

namespace vrv {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const fs::path& path, std::string reason) {
  std::replace(reason.begin(), reason.end(), '\n', ' ');
  throw std::runtime_error(fmt::format("{}: {}", path.string(), reason));
}

constexpr int kMaxSide = 1 << 16;
constexpr std::int64_t kMaxPixels = std::int64_t{1} << 28;

// One ulp of a floating type with `mantissa` stored bits at the magnitude `largest`.
double ulp_at(double largest, int mantissa) {
  if (!(largest > 0) || !std::isfinite(largest)) return 0;
  return std::ldexp(1.0, std::ilogb(largest) - mantissa);
}

// The quantum of ChannelImage for a stored pixel type (the image module's names).
double quantum_of(const fs::path& path, const std::string& type, double largest) {
  if (type == "uint8") return 1.0 / 255;
  if (type == "uint16") return 1.0 / 65535;
  if (type == "uint" || type == "uint32") return 1.0 / 4294967295.0;
  if (type == "half") return ulp_at(largest, 10);
  if (type == "float") return ulp_at(largest, 23);
  if (type == "double") return ulp_at(largest, 52);
  fail(path, fmt::format("pixel type {} is not supported", type));
}

}  // namespace

ChannelImage read_channel_image(const fs::path& path) {
  image_module::ReadRequest request;
  request.type = image_module::PixelType::float64;
  request.max_channels = 4;
  request.max_side = kMaxSide;
  request.max_pixels = kMaxPixels;
  const image_module::ReadResult read = image_module::read_file(path, request);
  ChannelImage img;
  img.width = read.width;
  img.height = read.height;
  const int nc = read.channels;
  img.alpha = read.alpha_channel;
  const std::vector<std::string> grey = {"Y"}, grey_alpha = {"Y", "A"}, rgb = {"R", "G", "B"},
                                  rgba = {"R", "G", "B", "A"};
  for (int c = 0; c < nc; ++c) {
    std::string name = c < static_cast<int>(read.channel_names.size()) ? read.channel_names[c] : "";
    if (name.empty()) name = (nc == 1 ? grey : nc == 2 ? grey_alpha : nc == 3 ? rgb : rgba)[c];
    img.names.push_back(name);
    if (img.alpha < 0 && (name == "A" || name == "a" || name == "alpha")) img.alpha = c;
  }
  if (img.alpha < 0 && (nc == 2 || nc == 4)) img.alpha = nc - 1;  // YA and RGBA by position
  img.planes.assign(nc, std::vector<double>(static_cast<std::size_t>(img.width) * img.height));
  double largest = 0;
  for (std::size_t i = 0; i < img.planes[0].size(); ++i)
    for (int c = 0; c < nc; ++c) {
      const double v = read.doubles[i * nc + c];
      img.planes[c][i] = v;
      if (std::isfinite(v)) largest = std::max(largest, std::abs(v));
    }
  img.pixel_type = read.pixel_type;
  img.quantum = quantum_of(path, img.pixel_type, largest);
  return img;
}

}  // namespace vrv
