#include "studies/engine/study_outputs.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "lib/io/atomic_file.h"

namespace vrv {

void write_table(const std::filesystem::path& dir, const std::string& stem, const Table& table,
                 const LatexStyle& style) {
  write_file_atomically(dir / (stem + ".csv"), table.to_csv());
  write_file_atomically(dir / (stem + ".md"), table.to_markdown());
  write_file_atomically(dir / (stem + ".tex"), table.to_latex(style));
}

double max_abs_pixel(const Image& image) {
  double m = 0;
  for (float v : image.pixels) m = std::max(m, std::abs(static_cast<double>(v)));
  return m;
}

void write_value_image(const Image& image, const std::filesystem::path& stem) {
  write_exr(image, stem.string() + ".exr");
  float hi = 0;
  for (float v : image.pixels) hi = std::max(hi, v);
  write_png_preview(image, stem.string() + ".png", 0, hi > 0 ? hi : 1);
}

void write_error_image(const Image& image, const std::filesystem::path& stem, double range) {
  write_exr(image, stem.string() + ".exr");
  write_error_map_png(image, stem.string() + ".png", range < 0 ? max_abs_pixel(image) : range);
}

double abs_pixel_quantile(const Image& image, double q) {
  if (image.pixels.empty()) return 0;
  std::vector<double> a(image.pixels.size());
  std::transform(image.pixels.begin(), image.pixels.end(), a.begin(),
                 [](float v) { return std::abs(static_cast<double>(v)); });
  const auto k = static_cast<std::size_t>(std::ceil(q * static_cast<double>(a.size())));
  const std::size_t rank = std::clamp<std::size_t>(k, 1, a.size()) - 1;
  std::nth_element(a.begin(), a.begin() + static_cast<long>(rank), a.end());
  return a[rank];
}

}  // namespace vrv
