#include "lib/io/image_io.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <system_error>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "lib/io/error_line.h"
#include "lib/io/image_module.h"

namespace vrv {
namespace {

namespace fs = std::filesystem;

// Largest side read_exr accepts, so that a hostile header cannot ask for terabytes.
constexpr int kMaxReadSide = 1 << 16;
constexpr std::int64_t kMaxReadPixels = std::int64_t{1} << 28;

template <class AnyImage>
void check_image(const AnyImage& image, const fs::path& path) {
  if (image.width < 1 || image.height < 1 || image.channels < 1 || image.channels > 4 ||
      image.pixels.size() != static_cast<std::size_t>(image.width) * image.height * image.channels)
    throw_file_error(path, fmt::format("bad image size {} x {} x {} channels with {} values", image.width,
                                       image.height, image.channels, image.pixels.size()));
}

// Writes the request with the image module to path + ".tmp", then renames it onto path.
void write_atomically(const fs::path& path, const image_module::WriteRequest& request) {
  const fs::path parent = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(parent, ec)) throw_file_error(path, "cannot write: the directory does not exist");
  if (fs::is_directory(path, ec)) throw_file_error(path, "cannot write: is a directory");
  fs::path tmp = path;
  tmp += ".tmp";
  const std::string why = image_module::functions().write(tmp.string(), request);
  if (!why.empty()) {
    fs::remove(tmp, ec);
    throw_file_error(path, fmt::format("cannot write: {}", why));
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw_file_error(path, fmt::format("cannot rename the temporary file onto it: {}", ec.message()));
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

void stamp(image_module::WriteRequest& r, const ImageProvenance* p) {
  if (!p) return;
  r.attributes.emplace_back("vrv:scene_hash", p->scene_hash);
  r.attributes.emplace_back("vrv:camera", p->camera);
  r.attributes.emplace_back("vrv:method", p->method);
  if (p->step) r.attributes.emplace_back("vrv:step", fmt::format("{:.17g}", *p->step));
  r.attributes.emplace_back("ImageDescription", p->to_json());
}

image_module::ReadResult read_header(const fs::path& path) {
  image_module::ReadRequest request;
  request.pixels = false;
  return image_module::read_file(path, request);
}

// The pixels of an image of 1 to max_channels channels, as `type`.
image_module::ReadResult read_pixels(const fs::path& path, image_module::PixelType type, int max_channels = 1) {
  image_module::ReadRequest request;
  request.type = type;
  request.max_channels = max_channels;
  request.max_side = kMaxReadSide;
  request.max_pixels = kMaxReadPixels;
  return image_module::read_file(path, request);
}

std::string attribute(const image_module::ReadResult& r, const std::string& name) {
  for (const auto& [key, value] : r.attributes)
    if (key == name) return value;
  return {};
}

unsigned char to_byte(double unit) {  // [0, 1] -> 0..255, rounded
  return static_cast<unsigned char>(std::lround(255 * std::clamp(unit, 0.0, 1.0)));
}

unsigned char mix(unsigned char a, unsigned char b, double t) {  // a + t (b - a), rounded
  return static_cast<unsigned char>(std::lround(a + t * (static_cast<double>(b) - a)));
}

}  // namespace

std::vector<std::string> channel_names(int channels) {
  switch (channels) {
    case 2: return {"Y", "A"};
    case 3: return {"R", "G", "B"};
    case 4: return {"R", "G", "B", "A"};
    default: return {"Y"};
  }
}

void check_image_shape(int w, int h, int c, std::optional<std::size_t> values) {
  if (w < 0 || h < 0) throw std::invalid_argument(fmt::format("image size {} x {}", w, h));
  if (c < 1 || c > 4) throw std::invalid_argument(fmt::format("image of {} channels (1 to 4)", c));
  const std::size_t expected = static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * static_cast<std::size_t>(c);
  if (values && *values != expected)
    throw std::invalid_argument(fmt::format("image of {} x {} x {} channels given {} values", w, h, c, *values));
}

void write_exr(const Image& image, const fs::path& path, const ImageProvenance* provenance) {
  check_image(image, path);
  auto r = request("openexr", image.width, image.height, image.channels, image_module::PixelType::float32,
                   image.pixels.data());
  r.channel_names = channel_names(image.channels);
  r.attributes = {{"compression", "zip"}};
  stamp(r, provenance);
  // OpenImageIO stamps EXRs with the time of writing unless told a date; an empty one keeps
  // reruns byte-identical (results/ must not change when the numbers do not).
  r.attributes.emplace_back("DateTime", "");
  write_atomically(path, r);
}

void write_png_preview(const Image& image, const fs::path& path, double lo, double hi,
                       const ImageProvenance* provenance) {
  check_image(image, path);
  if (!(hi > lo) || !std::isfinite(hi - lo))
    throw std::invalid_argument(
        fmt::format("{}: preview range [{}, {}] is empty or not finite", path.string(), lo, hi));
  std::vector<unsigned char> bytes(image.pixels.size());
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    const double v = image.pixels[i];
    bytes[i] = std::isnan(v) ? 0 : to_byte((v - lo) / (hi - lo));
  }
  auto r = request("png", image.width, image.height, image.channels, image_module::PixelType::uint8, bytes.data());
  r.channel_names = channel_names(image.channels);
  stamp(r, provenance);
  write_atomically(path, r);
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

Image8 error_map(const Image& error, double max_abs, int extra_columns) {
  if (std::isnan(max_abs)) throw std::invalid_argument("error map: the range is not a number");
  if (extra_columns < 0) throw std::invalid_argument(fmt::format("error map: {} extra columns", extra_columns));
  const int bar_x = error.width + kErrorBarGap, h = error.height;
  Image8 out(bar_x + kErrorBarWidth + extra_columns, h, 0, 3);
  auto put = [&](int x, int y, Rgb8 c) {
    unsigned char* p = &out.pixels[(static_cast<std::size_t>(y) * out.width + x) * 3];
    p[0] = c.r, p[1] = c.g, p[2] = c.b;
  };
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < error.width; ++x) put(x, y, diverging_colour(error.at(x, y), max_abs));
    // The bar: +max_abs on the top row, -max_abs on the bottom row, linear in between.
    const double v = h > 1 ? max_abs * (1 - 2.0 * y / (h - 1)) : 0.0;
    for (int x = bar_x; x < bar_x + kErrorBarWidth; ++x) put(x, y, diverging_colour(v, max_abs));
  }
  return out;
}

void write_error_map_png(const Image& error, const fs::path& path, double max_abs) {
  check_image(error, path);
  if (std::isnan(max_abs))
    throw std::invalid_argument(fmt::format("{}: error range is not a number", path.string()));
  write_rgb8_png(error_map(error, max_abs), path, fmt::format("signed error, colour range +-{:.6g}", max_abs));
}

void write_rgb8_png(const Image8& image, const fs::path& path, const std::string& description) {
  if (image.width < 1 || image.height < 1 || image.channels != 3 ||
      image.pixels.size() != static_cast<std::size_t>(image.width) * image.height * 3)
    throw_file_error(path, fmt::format("bad RGB image: {} x {} with {} channels and {} values", image.width,
                                       image.height, image.channels, image.pixels.size()));
  auto r = request("png", image.width, image.height, 3, image_module::PixelType::uint8, image.pixels.data());
  if (!description.empty()) r.attributes = {{"ImageDescription", description}};
  write_atomically(path, r);
}

Image read_exr(const fs::path& path) {
  image_module::ReadResult read = read_pixels(path, image_module::PixelType::float32);
  Image image;
  image.width = read.width;
  image.height = read.height;
  image.pixels = std::move(read.floats);
  return image;
}

std::string ImageProvenance::to_json() const {
  nlohmann::ordered_json j;
  j["scene_hash"] = scene_hash;
  j["camera"] = camera;
  j["method"] = method;
  if (step) j["step"] = *step;
  return nlohmann::ordered_json{{"vrv_provenance", j}}.dump();
}

namespace {

// The vrv:step attribute's text as the positive number vrv wrote (a damaged file's text is refused
// in one line: the image fuzzer found std::stod's exception ending the process).
double provenance_step(const fs::path& path, const std::string& text) {
  double step = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), step);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(step) || !(step > 0))
    throw_file_error(path, fmt::format("vrv:step: must be a positive number, got '{}'", cut_for_message(one_line(text), 40)));
  return step;
}

}  // namespace

std::optional<ImageProvenance> read_provenance(const fs::path& path) {
  if (path.extension() == ".npy") return std::nullopt;  // numpy arrays carry no metadata
  const image_module::ReadResult header = read_header(path);
  ImageProvenance p;
  p.scene_hash = attribute(header, "vrv:scene_hash");
  if (!p.scene_hash.empty()) {
    p.camera = attribute(header, "vrv:camera");
    p.method = attribute(header, "vrv:method");
    const std::string step = attribute(header, "vrv:step");
    if (!step.empty()) p.step = provenance_step(path, step);
    return p;
  }
  // Formats without free attributes: the JSON in ImageDescription.
  const auto j = nlohmann::json::parse(attribute(header, "ImageDescription"), nullptr, false);
  if (j.is_discarded() || !j.is_object() || !j.contains("vrv_provenance")) return std::nullopt;
  const auto& v = j["vrv_provenance"];
  if (!v.is_object() || !v.contains("scene_hash") || !v["scene_hash"].is_string())
    throw_file_error(path, "malformed vrv_provenance in ImageDescription");
  p.scene_hash = v["scene_hash"];
  p.camera = v.value("camera", "");
  p.method = v.value("method", "");
  if (v.contains("step") && v["step"].is_number()) p.step = v["step"].get<double>();
  if (p.step && !(std::isfinite(*p.step) && *p.step > 0))
    throw_file_error(path, fmt::format("vrv_provenance step: must be a positive number, got {}", *p.step));
  return p;
}

void write_tiff_f64(const ImageF64& image, const fs::path& path, const ImageProvenance* provenance) {
  check_image(image, path);
  auto r = request("tiff", image.width, image.height, image.channels, image_module::PixelType::float64,
                   image.pixels.data());
  r.channel_names = channel_names(image.channels);
  r.attributes = {{"compression", "zip"}, {"DateTime", ""}};
  stamp(r, provenance);
  write_atomically(path, r);
}

ImageInfo read_image_info(const fs::path& path) {
  const image_module::ReadResult header = read_header(path);
  ImageInfo info;
  info.width = header.width;
  info.height = header.height;
  info.channels = header.channels;
  info.format = header.format_name;
  info.pixel_type = header.pixel_type;
  info.floating = header.floating;
  info.bits = header.bits;
  return info;
}

ImageF64 read_image_f64(const fs::path& path, int max_channels) {
  image_module::ReadResult read = read_pixels(path, image_module::PixelType::float64, max_channels);
  return ImageF64{read.width, read.height, std::move(read.doubles), read.channels};
}

}  // namespace vrv
