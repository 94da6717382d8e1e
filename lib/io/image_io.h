#pragma once
// Images of one channel (grey, "Y") or three (RGB, "R", "G", "B", interleaved), each with alpha
// ("A") after them or not, in float or double, and their files, all through OpenImageIO: float
// OpenEXR for the numbers, 64-bit TIFF for every bit of a double, 8-bit PNG for looking at them.
//
// Every writer is atomic: it writes `<path>.tmp` in the same directory and renames it onto
// `path`, so an interrupted run never leaves a half-written file under the final name (the
// temporary is removed when writing fails).  Failures throw std::runtime_error, one line,
// naming the file.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace vrv {

// The channels' names for a count: "Y"; "Y", "A"; "R", "G", "B"; "R", "G", "B", "A".
std::vector<std::string> channel_names(int channels);

// Throws std::invalid_argument for a negative side, a channel count other than 1 to 4, or (when
// given) a pixel count other than w h channels values.
void check_image_shape(int w, int h, int channels, std::optional<std::size_t> values = std::nullopt);

// An image whose pixels are `channels` values of type T: float (Image) for EXR and the PNG
// previews, double (ImageF64) for the exact values a 64-bit TIFF keeps.
template <class T>
struct PixelImage {
  int width = 0, height = 0;
  std::vector<T> pixels;  // row-major, row 0 = top, `channels` values a pixel
  int channels = 1;       // 1 (grey), 3 (RGB), 2 or 4 (the same and alpha)

  PixelImage() = default;
  // Throws std::invalid_argument for a negative side or a channel count other than 1 to 4.
  PixelImage(int w, int h, T fill = 0, int channels = 1) : width(w), height(h), channels(channels) {
    check_image_shape(w, h, channels);
    pixels.assign(static_cast<std::size_t>(w) * h * channels, fill);
  }
  // The given pixels; throws std::invalid_argument as above, or when they are not w h channels values.
  PixelImage(int w, int h, std::vector<T> given, int channels = 1)
      : width(w), height(h), pixels(std::move(given)), channels(channels) {
    check_image_shape(w, h, channels, pixels.size());
  }
  // A one-channel image's pixel.
  T& at(int x, int y) { return pixels[static_cast<std::size_t>(y) * width + x]; }
  T at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
  // Channel c of pixel i (row-major from the top left), any channel count.
  T& value(std::size_t i, int c) { return pixels[i * channels + c]; }
  T value(std::size_t i, int c) const { return pixels[i * channels + c]; }
  std::size_t pixel_count() const { return static_cast<std::size_t>(width) * static_cast<std::size_t>(height); }
};
using Image = PixelImage<float>;
using ImageF64 = PixelImage<double>;
using Image8 = PixelImage<unsigned char>;  // 8-bit pictures (the error maps' PNG), 0 to 255

// The pixels rounded to float: what EXR and the previews store.
inline Image to_float(const ImageF64& image) {
  return Image(image.width, image.height, std::vector<float>(image.pixels.begin(), image.pixels.end()), image.channels);
}

// Where an image came from, so that a verification can refuse a reference of another scene or
// camera.  Written into the image's metadata by the writers below when given: as the string
// attributes "vrv:scene_hash", "vrv:camera", "vrv:method" and "vrv:step" (EXR keeps them as
// header attributes) and, for formats without free attributes (TIFF, PNG), as the JSON of
// to_json() in ImageDescription.
struct ImageProvenance {
  std::string scene_hash;       // scene_hash(scene, camera) of lib/scene_hash.h, 40 hex digits
  std::string camera;           // camera_description(camera) of lib/scene_hash.h
  std::string method;           // e.g. "reference tol=1e-12", "alpha step h=0.01 double"
  std::optional<double> step;   // world sample distance of a step-based discrete method

  // {"vrv_provenance": {"scene_hash": ..., "camera": ..., "method": ..., "step": ...}}
  std::string to_json() const;
};

// The provenance stored in an image file, or nothing when it carries none.  Throws
// std::runtime_error naming the file when it cannot be read.
std::optional<ImageProvenance> read_provenance(const std::filesystem::path& path);

// 32-bit float, channels named by channel_names, lossless (zip) compression: bit-exact round trip.
void write_exr(const Image& image, const std::filesystem::path& path,
               const ImageProvenance* provenance = nullptr);

// 64-bit float TIFF, its channels as write_exr names them, zip compression: every double bit for
// bit (the EXR beside it rounds to float, one float ulp = 6e-8 near 1, which would hide smaller errors).
void write_tiff_f64(const ImageF64& image, const std::filesystem::path& path,
                    const ImageProvenance* provenance = nullptr);

// What a file holds, without reading its pixels.
struct ImageInfo {
  int width = 0, height = 0, channels = 0;
  std::string format;      // OpenImageIO's format name: "openexr", "tiff", "png", ...
  std::string pixel_type;  // "uint8", "uint16", "half", "float", "double", ...
  bool floating = false;   // half, float or double pixels
  int bits = 0;            // bits per channel value
};
ImageInfo read_image_info(const std::filesystem::path& path);

// The first subimage of an image of 1 to max_channels channels as doubles (float64 TIFF exactly;
// narrower types widened).  The same checks and errors as read_exr.
ImageF64 read_image_f64(const std::filesystem::path& path, int max_channels = 1);

// 8-bit grey or RGB: round(255 * clamp((v - lo) / (hi - lo), 0, 1)) per channel; NaN becomes 0.  Needs hi > lo
// (std::invalid_argument otherwise).
void write_png_preview(const Image& image, const std::filesystem::path& path, double lo, double hi,
                       const ImageProvenance* provenance = nullptr);

// Signed values as 8-bit RGB with a diverging map over [-max_abs, +max_abs]: blue (33, 102,
// 172) at -max_abs, white (255, 255, 255) at 0, red (178, 24, 43) at +max_abs, linear in
// between and clamped beyond; NaN is black.  max_abs <= 0 maps everything finite to white.
// A colour bar follows on the right: kErrorBarGap black columns, then kErrorBarWidth columns
// running from +max_abs (top row) to -max_abs (bottom row).  The range is stored in the PNG
// as ImageDescription "signed error, colour range +-<max_abs>".
inline constexpr int kErrorBarGap = 2;
inline constexpr int kErrorBarWidth = 8;
void write_error_map_png(const Image& error, const std::filesystem::path& path, double max_abs);

// The diverging map above, for one value: {r, g, b}.
struct Rgb8 {
  unsigned char r = 0, g = 0, b = 0;
};
Rgb8 diverging_colour(double value, double max_abs);

// The map and its bar as write_error_map_png draws them (3 channels), with `extra_columns` black
// columns after the bar (room for labels).  std::invalid_argument for a NaN max_abs or negative
// extra_columns.
Image8 error_map(const Image& error, double max_abs, int extra_columns = 0);

// A 3-channel 8-bit image written atomically as PNG with `description` as its ImageDescription
// (empty: none).
void write_rgb8_png(const Image8& image, const std::filesystem::path& path, const std::string& description);

// Reads the first subimage of a one-channel image (EXR or anything OIIO reads) as floats.
// Throws std::runtime_error naming the file when it cannot be read or has other than one channel.
Image read_exr(const std::filesystem::path& path);

}  // namespace vrv
