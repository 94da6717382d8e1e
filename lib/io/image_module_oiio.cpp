// The image module: the only code that includes OpenImageIO.  Built as a shared module
// (libvrv_image.so) and loaded by lib/io/image_module.cpp on the first image read or write.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include "lib/io/error_line.h"
#include "lib/io/image_module.h"
#include "lib/io/stderr_capture.h"

namespace vrv::image_module {
namespace {

// OpenImageIO's message on one line (lib/io/error_line), or a word when it gave none.
std::string one_line(std::string s) {
  s = vrv::one_line(std::move(s));
  return s.empty() ? std::string("unknown error") : s;
}

OIIO::TypeDesc type_of(PixelType t) {
  switch (t) {
    case PixelType::float64: return OIIO::TypeDesc::DOUBLE;
    case PixelType::uint8: return OIIO::TypeDesc::UINT8;
    default: return OIIO::TypeDesc::FLOAT;
  }
}

std::string write(const std::string& path, const WriteRequest& request) try {
  const OIIO::TypeDesc type = type_of(request.type);
  OIIO::ImageSpec spec(request.width, request.height, request.channels, type);
  if (!request.channel_names.empty()) spec.channelnames = request.channel_names;
  // A TIFF keeps no channel names, only what the samples are: named alpha is declared alpha, so
  // Y, A reads back as grey and alpha (not "R, G").  EXR keeps the names (an error image's A is
  // an error, not alpha).
  if (request.format == "tiff") {
    const auto alpha = std::find(spec.channelnames.begin(), spec.channelnames.end(), "A");
    spec.alpha_channel = alpha == spec.channelnames.end() ? -1 : static_cast<int>(alpha - spec.channelnames.begin());
  }
  for (const auto& [key, value] : request.attributes) spec.attribute(key, value);
  auto out = OIIO::ImageOutput::create(request.format);
  if (!out) return one_line(fmt::format("no {} writer in OpenImageIO: {}", request.format, OIIO::geterror()));
  if (!out->open(path, spec)) return one_line(out->geterror());
  const bool wrote = out->write_image(type, request.pixels);
  std::string why = wrote ? std::string() : out->geterror();
  const bool closed = out->close();
  if (!closed && why.empty()) why = out->geterror();
  return wrote && closed ? std::string() : one_line(why);
} catch (const std::exception& e) {
  return one_line(e.what());
}

// libpng reports a damaged file twice: to OpenImageIO's error handler, which vrv's one line quotes,
// and then (that handler returns where libpng expects it to jump) through libpng's default handler
// straight to stderr, "libpng error: ...", a second line before vrv's.  OpenImageIO has no option
// to silence it, so a read runs with stderr captured: what it caught is dropped when the read
// failed (the error names it) and passed on when it succeeded.
std::string read_captured(const std::string& path, const ReadRequest& request, ReadResult& result);

std::string read(const std::string& path, const ReadRequest& request, ReadResult& result) {
  StderrCapture capture;
  const std::string why = read_captured(path, request, result);
  const std::string said = capture.release();
  if (why.empty() && !said.empty()) std::fputs(said.c_str(), stderr);
  return why;
}

std::string read_captured(const std::string& path, const ReadRequest& request, ReadResult& result) try {
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path, request.keep_straight_alpha ? &config : nullptr);
  if (!in) return one_line(fmt::format("cannot read: {}", OIIO::geterror()));
  const OIIO::ImageSpec& spec = in->spec();
  result.width = spec.width;
  result.height = spec.height;
  result.depth = spec.depth;
  result.channels = spec.nchannels;
  result.deep = spec.deep;
  result.format_name = in->format_name();
  result.pixel_type = spec.format.c_str();
  result.floating = spec.format.is_floating_point();
  result.bits = spec.get_int_attribute("oiio:BitsPerSample", static_cast<int>(spec.format.size() * 8));
  result.channel_names = spec.channelnames;
  result.alpha_channel = spec.alpha_channel;
  result.straight_alpha = request.keep_straight_alpha && spec.get_int_attribute("oiio:UnassociatedAlpha", 0) != 0;
  for (const OIIO::ParamValue& p : spec.extra_attribs)
    result.attributes.emplace_back(p.name().string(), p.get_string());
  if (!request.pixels) return {};
  if (spec.deep) return "deep images are not supported";
  if (spec.depth != 1) return fmt::format("expected a 2D image, got depth {}", spec.depth);
  if (request.max_channels == 1 && spec.nchannels != 1)
    return fmt::format("expected one channel, got {}", spec.nchannels);
  if (spec.nchannels < 1 || spec.nchannels > request.max_channels)
    return fmt::format("expected 1 to {} channels (grey, grey+alpha, RGB, RGBA), got {}",
                       request.max_channels, spec.nchannels);
  if (spec.width < 1 || spec.height < 1 || spec.width > request.max_side ||
      spec.height > request.max_side ||
      static_cast<long long>(spec.width) * spec.height > request.max_pixels)
    return fmt::format("bad image size {} x {}", spec.width, spec.height);
  const std::size_t n = static_cast<std::size_t>(spec.width) * spec.height * spec.nchannels;
  void* data = nullptr;
  if (request.type == PixelType::float64) {
    result.doubles.assign(n, 0.0);
    data = result.doubles.data();
  } else if (request.type == PixelType::float32) {
    result.floats.assign(n, 0.0f);
    data = result.floats.data();
  } else {
    return "pixels are read as float32 or float64";
  }
  if (!in->read_image(0, 0, 0, spec.nchannels, type_of(request.type), data))
    return one_line(fmt::format("cannot read: {}", in->geterror()));
  in->close();
  return {};
} catch (const std::exception& e) {
  return one_line(e.what());
}

const Functions kFunctions{kAbiVersion, &write, &read};

}  // namespace
}  // namespace vrv::image_module

extern "C" __attribute__((visibility("default"))) const vrv::image_module::Functions*
vrv_image_module_functions() {
  return &vrv::image_module::kFunctions;
}
