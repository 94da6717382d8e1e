#include "lib/io/image_io.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <system_error>

#include <fmt/format.h>

#include "lib/io/image_module.h"

namespace vrv {
namespace {

namespace fs = std::filesystem;

// Largest side read_exr accepts, so that a hostile header cannot ask for terabytes.
constexpr int kMaxReadSide = 1 << 16;
constexpr std::int64_t kMaxReadPixels = std::int64_t{1} << 28;

std::string one_line(std::string s) {
  std::replace_if(s.begin(), s.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

[[noreturn]] void fail(const fs::path& path, const std::string& reason) {
  throw std::runtime_error(one_line(fmt::format("{}: {}", path.string(), reason)));
}

void check_image(const Image& image, const fs::path& path) {
  if (image.width < 1 || image.height < 1 ||
      image.pixels.size() != static_cast<std::size_t>(image.width) * image.height)
    fail(path, fmt::format("bad image size {} x {} with {} pixels", image.width, image.height,
                           image.pixels.size()));
}

// Writes the request with the image module to path + ".tmp", then renames it onto path.
void write_atomically(const fs::path& path, image_module::WriteRequest request) {
  const fs::path parent = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(parent, ec)) fail(path, "cannot write: the directory does not exist");
  if (fs::is_directory(path, ec)) fail(path, "cannot write: is a directory");
  fs::path tmp = path;
  tmp += ".tmp";
  const std::string why = image_module::functions().write(tmp.string(), request);
  if (!why.empty()) {
    fs::remove(tmp, ec);
    fail(path, fmt::format("cannot write: {}", why));
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    fail(path, fmt::format("cannot rename the temporary file onto it: {}", ec.message()));
  }
}

image_module::WriteRequest request(const char* format, int width, int height, int channels,
                                   image_module::PixelType type, const void* pixels) {
  image_module::WriteRequest r;
  r.format = format;
  r.width = width;
  r.height = height;
  r.channels = channels;
  r.type = type;
  r.pixels = pixels;
  return r;
}

unsigned char to_byte(double unit) {  // [0, 1] -> 0..255, rounded
  return static_cast<unsigned char>(std::lround(255 * std::clamp(unit, 0.0, 1.0)));
}

unsigned char mix(unsigned char a, unsigned char b, double t) {  // a + t (b - a), rounded
  return static_cast<unsigned char>(std::lround(a + t * (static_cast<double>(b) - a)));
}

}  // namespace

Image::Image(int w, int h, float fill) : width(w), height(h) {
  if (w < 0 || h < 0) throw std::invalid_argument(fmt::format("image size {} x {}", w, h));
  pixels.assign(static_cast<std::size_t>(w) * h, fill);
}

void write_exr(const Image& image, const fs::path& path) {
  check_image(image, path);
  auto r = request("openexr", image.width, image.height, 1, image_module::PixelType::float32,
                   image.pixels.data());
  r.channel_names = {"Y"};
  // OpenImageIO stamps EXRs with the time of writing unless told a date; an empty one keeps
  // reruns byte-identical (results/ must not change when the numbers do not).
  r.attributes = {{"compression", "zip"}, {"DateTime", ""}};
  write_atomically(path, std::move(r));
}

void write_png_preview(const Image& image, const fs::path& path, double lo, double hi) {
  check_image(image, path);
  if (!(hi > lo) || !std::isfinite(hi - lo))
    throw std::invalid_argument(
        fmt::format("{}: preview range [{}, {}] is empty or not finite", path.string(), lo, hi));
  std::vector<unsigned char> bytes(image.pixels.size());
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    const double v = image.pixels[i];
    bytes[i] = std::isnan(v) ? 0 : to_byte((v - lo) / (hi - lo));
  }
  auto r = request("png", image.width, image.height, 1, image_module::PixelType::uint8, bytes.data());
  r.channel_names = {"Y"};
  write_atomically(path, std::move(r));
}

Rgb8 diverging_colour(double value, double max_abs) {
  constexpr Rgb8 blue{33, 102, 172}, white{255, 255, 255}, red{178, 24, 43};
  if (std::isnan(value)) return {};
  if (!(max_abs > 0)) return white;
  const double t = std::clamp(value / max_abs, -1.0, 1.0);
  const Rgb8 end = t < 0 ? blue : red;
  const double s = std::abs(t);
  return {mix(white.r, end.r, s), mix(white.g, end.g, s), mix(white.b, end.b, s)};
}

void write_error_map_png(const Image& error, const fs::path& path, double max_abs) {
  check_image(error, path);
  if (std::isnan(max_abs))
    throw std::invalid_argument(fmt::format("{}: error range is not a number", path.string()));
  const int w = error.width + kErrorBarGap + kErrorBarWidth, h = error.height;
  std::vector<unsigned char> rgb(static_cast<std::size_t>(w) * h * 3, 0);
  auto put = [&](int x, int y, Rgb8 c) {
    unsigned char* p = &rgb[(static_cast<std::size_t>(y) * w + x) * 3];
    p[0] = c.r, p[1] = c.g, p[2] = c.b;
  };
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < error.width; ++x) put(x, y, diverging_colour(error.at(x, y), max_abs));
    // The bar: +max_abs on the top row, -max_abs on the bottom row, linear in between.
    const double v = h > 1 ? max_abs * (1 - 2.0 * y / (h - 1)) : 0.0;
    for (int x = error.width + kErrorBarGap; x < w; ++x) put(x, y, diverging_colour(v, max_abs));
  }
  auto r = request("png", w, h, 3, image_module::PixelType::uint8, rgb.data());
  r.attributes = {{"ImageDescription", fmt::format("signed error, colour range +-{:.6g}", max_abs)}};
  write_atomically(path, std::move(r));
}

Image read_exr(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) fail(path, "cannot read: no such file");
  if (fs::is_directory(path, ec)) fail(path, "cannot read: is a directory");
  image_module::ReadRequest request;
  request.max_side = kMaxReadSide;
  request.max_pixels = kMaxReadPixels;
  image_module::ReadResult read;
  const std::string why = image_module::functions().read(path.string(), request, read);
  if (!why.empty()) fail(path, why);
  Image image;
  image.width = read.width;
  image.height = read.height;
  image.pixels = std::move(read.floats);
  return image;
}

}  // namespace vrv
