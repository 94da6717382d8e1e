#pragma once
// Single-channel float images and their files, all through OpenImageIO: float OpenEXR for the
// numbers, 8-bit PNG for looking at them.
//
// Every writer is atomic: it writes `<path>.tmp` in the same directory and renames it onto
// `path`, so an interrupted run never leaves a half-written file under the final name (the
// temporary is removed when writing fails).  Failures throw std::runtime_error, one line,
// naming the file.
#include <filesystem>
#include <vector>

namespace vrv {

struct Image {
  int width = 0, height = 0;
  std::vector<float> pixels;  // one channel, row-major, row 0 = top

  Image() = default;
  Image(int w, int h, float fill = 0);  // throws std::invalid_argument for a negative side
  float& at(int x, int y) { return pixels[static_cast<std::size_t>(y) * width + x]; }
  float at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
};

// 32-bit float, one channel named "Y", lossless (zip) compression: bit-exact round trip.
void write_exr(const Image& image, const std::filesystem::path& path);

// 8-bit grey: round(255 * clamp((v - lo) / (hi - lo), 0, 1)); NaN becomes 0.  Needs hi > lo
// (std::invalid_argument otherwise).
void write_png_preview(const Image& image, const std::filesystem::path& path, double lo, double hi);

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

// Reads the first subimage of a one-channel image (EXR or anything OIIO reads) as floats.
// Throws std::runtime_error naming the file when it cannot be read or has other than one channel.
Image read_exr(const std::filesystem::path& path);

}  // namespace vrv
