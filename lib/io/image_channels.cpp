#include "lib/io/image_channels.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

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

}  // namespace

ChannelImage read_channel_image(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) fail(path, "cannot read: no such file");
  if (fs::is_directory(path, ec)) fail(path, "cannot read: is a directory");
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) fail(path, fmt::format("cannot read: {}", OIIO::geterror()));
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.deep) fail(path, "deep images are not supported");
  if (spec.depth != 1) fail(path, fmt::format("expected a 2D image, got depth {}", spec.depth));
  if (spec.nchannels < 1 || spec.nchannels > 4)
    fail(path, fmt::format("expected 1 to 4 channels (grey, grey+alpha, RGB, RGBA), got {}", spec.nchannels));
  if (spec.width < 1 || spec.height < 1 || spec.width > kMaxSide || spec.height > kMaxSide ||
      std::int64_t{spec.width} * spec.height > kMaxPixels)
    fail(path, fmt::format("bad image size {} x {}", spec.width, spec.height));
  ChannelImage img;
  img.width = spec.width;
  img.height = spec.height;
  const int nc = spec.nchannels;
  std::vector<double> interleaved(static_cast<std::size_t>(img.width) * img.height * nc);
  if (!in->read_image(0, 0, 0, nc, OIIO::TypeDesc::DOUBLE, interleaved.data()))
    fail(path, fmt::format("cannot read: {}", in->geterror()));
  in->close();
  img.alpha = spec.alpha_channel;
  const std::vector<std::string> grey = {"Y"}, grey_alpha = {"Y", "A"}, rgb = {"R", "G", "B"},
                                  rgba = {"R", "G", "B", "A"};
  for (int c = 0; c < nc; ++c) {
    std::string name = c < static_cast<int>(spec.channelnames.size()) ? spec.channelnames[c] : "";
    if (name.empty()) name = (nc == 1 ? grey : nc == 2 ? grey_alpha : nc == 3 ? rgb : rgba)[c];
    img.names.push_back(name);
    if (img.alpha < 0 && (name == "A" || name == "a" || name == "alpha")) img.alpha = c;
  }
  if (img.alpha < 0 && (nc == 2 || nc == 4)) img.alpha = nc - 1;  // YA and RGBA by position
  img.planes.assign(nc, std::vector<double>(static_cast<std::size_t>(img.width) * img.height));
  double largest = 0;
  for (std::size_t i = 0; i < img.planes[0].size(); ++i)
    for (int c = 0; c < nc; ++c) {
      const double v = interleaved[i * nc + c];
      img.planes[c][i] = v;
      if (std::isfinite(v)) largest = std::max(largest, std::abs(v));
    }
  const OIIO::TypeDesc t = spec.format;
  img.pixel_type = t.c_str();
  if (t == OIIO::TypeDesc::UINT8) img.quantum = 1.0 / 255;
  else if (t == OIIO::TypeDesc::UINT16) img.quantum = 1.0 / 65535;
  else if (t == OIIO::TypeDesc::HALF) img.quantum = ulp_at(largest, 10);
  else if (t == OIIO::TypeDesc::FLOAT) img.quantum = ulp_at(largest, 23);
  else if (t == OIIO::TypeDesc::DOUBLE) img.quantum = ulp_at(largest, 52);
  else if (t.basetype == OIIO::TypeDesc::UINT32) img.quantum = 1.0 / 4294967295.0;
  else fail(path, fmt::format("pixel type {} is not supported", img.pixel_type));
  return img;
}

}  // namespace vrv
