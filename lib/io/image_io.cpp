#include "lib/io/image_io.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <system_error>

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

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

// Writes `data` (laid out as `spec` says, in `type`) with the writer for `format` to
// path + ".tmp", then renames it onto path.
void write_atomically(const fs::path& path, const char* format, const OIIO::ImageSpec& spec,
                      OIIO::TypeDesc type, const void* data) {
  const fs::path parent = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(parent, ec)) fail(path, "cannot write: the directory does not exist");
  if (fs::is_directory(path, ec)) fail(path, "cannot write: is a directory");
  fs::path tmp = path;
  tmp += ".tmp";
  auto out = OIIO::ImageOutput::create(format);
  if (!out) fail(path, fmt::format("no {} writer in OpenImageIO: {}", format, OIIO::geterror()));
  if (!out->open(tmp.string(), spec)) {
    const std::string why = out->geterror();
    out.reset();
    fs::remove(tmp, ec);
    fail(path, fmt::format("cannot write: {}", why));
  }
  const bool wrote = out->write_image(type, data);
  std::string why = wrote ? std::string() : out->geterror();
  const bool closed = out->close();
  if (!closed && why.empty()) why = out->geterror();
  out.reset();
  if (!wrote || !closed) {
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

void stamp(OIIO::ImageSpec& spec, const ImageProvenance* p) {
  if (!p) return;
  spec.attribute("vrv:scene_hash", p->scene_hash);
  spec.attribute("vrv:camera", p->camera);
  spec.attribute("vrv:method", p->method);
  if (p->step) spec.attribute("vrv:step", fmt::format("{:.17g}", *p->step));
  spec.attribute("ImageDescription", p->to_json());
}

// Opens an image file for reading, or throws naming the file.
std::unique_ptr<OIIO::ImageInput> open_image(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) fail(path, "cannot read: no such file");
  if (fs::is_directory(path, ec)) fail(path, "cannot read: is a directory");
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) fail(path, fmt::format("cannot read: {}", OIIO::geterror()));
  return in;
}

// Opens the first subimage for reading with the checks every pixel reader shares.
std::unique_ptr<OIIO::ImageInput> open_one_channel(const fs::path& path) {
  auto in = open_image(path);
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.deep) fail(path, "deep images are not supported");
  if (spec.nchannels != 1)
    fail(path, fmt::format("expected one channel, got {}", spec.nchannels));
  if (spec.depth != 1) fail(path, fmt::format("expected a 2D image, got depth {}", spec.depth));
  if (spec.width < 1 || spec.height < 1 || spec.width > kMaxReadSide ||
      spec.height > kMaxReadSide ||
      std::int64_t{spec.width} * spec.height > kMaxReadPixels)
    fail(path, fmt::format("bad image size {} x {}", spec.width, spec.height));
  return in;
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

void write_exr(const Image& image, const fs::path& path, const ImageProvenance* provenance) {
  check_image(image, path);
  OIIO::ImageSpec spec(image.width, image.height, 1, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"Y"};
  spec.attribute("compression", "zip");
  stamp(spec, provenance);
  // OpenImageIO stamps EXRs with the time of writing unless told a date; an empty one keeps
  // reruns byte-identical (results/ must not change when the numbers do not).
  spec.attribute("DateTime", "");
  write_atomically(path, "openexr", spec, OIIO::TypeDesc::FLOAT, image.pixels.data());
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
  OIIO::ImageSpec spec(image.width, image.height, 1, OIIO::TypeDesc::UINT8);
  spec.channelnames = {"Y"};
  stamp(spec, provenance);
  write_atomically(path, "png", spec, OIIO::TypeDesc::UINT8, bytes.data());
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
  OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::UINT8);
  spec.attribute("ImageDescription", fmt::format("signed error, colour range +-{:.6g}", max_abs));
  write_atomically(path, "png", spec, OIIO::TypeDesc::UINT8, rgb.data());
}

void write_rgb8_png(int width, int height, const std::vector<unsigned char>& rgb, const fs::path& path,
                    const std::string& description) {
  if (width < 1 || height < 1 || rgb.size() != static_cast<std::size_t>(width) * height * 3)
    fail(path, fmt::format("bad RGB image size {} x {} with {} bytes", width, height, rgb.size()));
  OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  if (!description.empty()) spec.attribute("ImageDescription", description);
  write_atomically(path, "png", spec, OIIO::TypeDesc::UINT8, rgb.data());
}

Image read_exr(const fs::path& path) {
  auto in = open_one_channel(path);
  const OIIO::ImageSpec& spec = in->spec();
  Image image(spec.width, spec.height);
  if (!in->read_image(0, 0, 0, 1, OIIO::TypeDesc::FLOAT, image.pixels.data()))
    fail(path, fmt::format("cannot read: {}", in->geterror()));
  in->close();
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

std::optional<ImageProvenance> read_provenance(const fs::path& path) {
  auto in = open_image(path);
  const OIIO::ImageSpec& spec = in->spec();
  ImageProvenance p;
  p.scene_hash = spec.get_string_attribute("vrv:scene_hash");
  if (!p.scene_hash.empty()) {
    p.camera = spec.get_string_attribute("vrv:camera");
    p.method = spec.get_string_attribute("vrv:method");
    const std::string step = spec.get_string_attribute("vrv:step");
    if (!step.empty()) p.step = std::stod(step);
    return p;
  }
  // Formats without free attributes: the JSON in ImageDescription.
  const auto j = nlohmann::json::parse(spec.get_string_attribute("ImageDescription"), nullptr, false);
  if (j.is_discarded() || !j.is_object() || !j.contains("vrv_provenance")) return std::nullopt;
  const auto& v = j["vrv_provenance"];
  if (!v.is_object() || !v.contains("scene_hash") || !v["scene_hash"].is_string())
    fail(path, "malformed vrv_provenance in ImageDescription");
  p.scene_hash = v["scene_hash"];
  p.camera = v.value("camera", "");
  p.method = v.value("method", "");
  if (v.contains("step") && v["step"].is_number()) p.step = v["step"].get<double>();
  return p;
}

void write_tiff_f64(const ImageF64& image, const fs::path& path, const ImageProvenance* provenance) {
  if (image.width < 1 || image.height < 1 ||
      image.pixels.size() != static_cast<std::size_t>(image.width) * image.height)
    fail(path, fmt::format("bad image size {} x {} with {} pixels", image.width, image.height,
                           image.pixels.size()));
  OIIO::ImageSpec spec(image.width, image.height, 1, OIIO::TypeDesc::DOUBLE);
  spec.channelnames = {"Y"};
  spec.attribute("compression", "zip");
  spec.attribute("DateTime", "");
  stamp(spec, provenance);
  write_atomically(path, "tiff", spec, OIIO::TypeDesc::DOUBLE, image.pixels.data());
}

ImageInfo read_image_info(const fs::path& path) {
  auto in = open_image(path);
  const OIIO::ImageSpec& spec = in->spec();
  ImageInfo info;
  info.width = spec.width;
  info.height = spec.height;
  info.channels = spec.nchannels;
  info.format = in->format_name();
  info.pixel_type = spec.format.c_str();
  info.floating = spec.format.is_floating_point();
  info.bits = spec.get_int_attribute("oiio:BitsPerSample", static_cast<int>(spec.format.size() * 8));
  return info;
}

ImageF64 read_image_f64(const fs::path& path) {
  auto in = open_one_channel(path);
  const OIIO::ImageSpec& spec = in->spec();
  ImageF64 image{spec.width, spec.height, std::vector<double>(static_cast<std::size_t>(spec.width) * spec.height)};
  if (!in->read_image(0, 0, 0, 1, OIIO::TypeDesc::DOUBLE, image.pixels.data()))
    fail(path, fmt::format("cannot read: {}", in->geterror()));
  in->close();
  return image;
}

}  // namespace vrv
