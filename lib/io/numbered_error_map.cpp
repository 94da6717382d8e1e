#include "lib/io/numbered_error_map.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace vrv {
namespace {

// A 3 x 5 pixel font for the characters a number needs.  Hand-rolled because OpenImageIO's
// render_text needs FreeType and a TrueType font, which a minimal Debian install (the README's
// package list) does not have; 14 glyphs are shorter than a font dependency.
constexpr int kGlyphW = 3, kGlyphH = 5, kScale = 1;
std::array<unsigned char, kGlyphH> glyph(char c) {
  switch (c) {  // rows top to bottom, bit 2 = left column
    case '0': return {7, 5, 5, 5, 7};
    case '1': return {2, 6, 2, 2, 7};
    case '2': return {7, 1, 7, 4, 7};
    case '3': return {7, 1, 7, 1, 7};
    case '4': return {5, 5, 7, 1, 1};
    case '5': return {7, 4, 7, 1, 7};
    case '6': return {7, 4, 7, 5, 7};
    case '7': return {7, 1, 1, 1, 1};
    case '8': return {7, 5, 7, 5, 7};
    case '9': return {7, 5, 7, 1, 7};
    case '.': return {0, 0, 0, 0, 2};
    case '-': return {0, 0, 7, 0, 0};
    case '+': return {0, 2, 7, 2, 0};
    case 'e': return {0, 7, 7, 4, 7};
    default: return {0, 0, 0, 0, 0};
  }
}

constexpr int kAdvance = (kGlyphW + 1) * kScale;
constexpr int kLabelChars = 9;  // "+1.2e-03" and room
constexpr int kLabelGap = 2;

}  // namespace

std::string bar_label(double value) {
  if (value == 0) return "0";
  return fmt::format("{:+.1e}", value);
}

Image8 numbered_error_map(const Image& error, double max_abs) {
  const int label_x = error.width + kErrorBarGap + kErrorBarWidth + kLabelGap;
  Image8 out = error_map(error, max_abs, kLabelGap + kLabelChars * kAdvance);
  auto put = [&](int x, int y, Rgb8 c) {
    if (x < 0 || y < 0 || x >= out.width || y >= out.height) return;
    unsigned char* p = &out.pixels[(static_cast<std::size_t>(y) * out.width + x) * 3];
    p[0] = c.r, p[1] = c.g, p[2] = c.b;
  };
  const int h = error.height;
  // Labels at the rows of +max, +max/2, 0, -max/2, -max, as many as fit without overlapping.
  const int label_h = kGlyphH * kScale + 1;
  const int count = h >= 5 * label_h ? 5 : h >= 3 * label_h ? 3 : h >= label_h ? 1 : 0;
  const Rgb8 white{255, 255, 255};
  for (int k = 0; k < count; ++k) {
    const double frac = count == 1 ? 0.5 : static_cast<double>(k) / (count - 1);  // 0 = top
    const int row = static_cast<int>(std::lround(frac * (h - 1)));
    const double value = max_abs * (1 - 2 * frac);
    const int top = std::clamp(row - kGlyphH * kScale / 2, 0, std::max(0, h - kGlyphH * kScale));
    const std::string text = bar_label(value);
    for (std::size_t i = 0; i < text.size() && static_cast<int>(i) < kLabelChars; ++i) {
      const auto g = glyph(text[i]);
      for (int gy = 0; gy < kGlyphH * kScale; ++gy)
        for (int gx = 0; gx < kGlyphW * kScale; ++gx)
          if (g[gy / kScale] & (4 >> (gx / kScale)))
            put(label_x + static_cast<int>(i) * kAdvance + gx, top + gy, white);
    }
  }
  return out;
}

void write_numbered_error_map_png(const Image& error, const std::filesystem::path& path, double max_abs) {
  write_rgb8_png(numbered_error_map(error, max_abs), path, fmt::format("signed error, colour range +-{:.6g}", max_abs));
}

}  // namespace vrv
