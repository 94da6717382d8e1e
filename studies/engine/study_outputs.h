#pragma once
// What a study writes into its folder besides checks.* and meta.json: a table as stem.csv,
// stem.md and stem.tex; a value image as a float EXR with a grey PNG preview; an error image as a
// float EXR with a diverging colour-mapped PNG (each scaled to its own largest magnitude).
#include <filesystem>
#include <string>

#include "lib/io/image_io.h"
#include "lib/io/table.h"

namespace vrv {

// stem.csv, stem.md and stem.tex (with `style`), each written atomically.
void write_table(const std::filesystem::path& dir, const std::string& stem, const Table& table,
                 const LatexStyle& style = {});

// The largest |pixel| (0 for an empty image).
double max_abs_pixel(const Image& image);

// stem.exr and stem.png: the preview spans [0, largest value] (1 when nothing is positive).
void write_value_image(const Image& image, const std::filesystem::path& stem);
// stem.exr and stem.png: the map spans +- range (default max_abs_pixel(image)), clamped beyond.
void write_error_image(const Image& image, const std::filesystem::path& stem, double range = -1);
// The q-quantile (0 <= q <= 1) of |pixel|, by nearest rank (0 for an empty image).
double abs_pixel_quantile(const Image& image, double q);

}  // namespace vrv
