#pragma once
// A signed error image as a colour-mapped PNG whose colour bar carries numbers: the diverging map
// of write_error_map_png (lib/image_io.h) with the bar's values (+max, +max/2, 0, -max/2, -max, as
// many as fit) written beside it, so the picture can be read without its metadata.
#include <filesystem>
#include <string>
#include <vector>

#include "lib/io/image_io.h"

namespace vrv {

// The RGB pixels (3 channels, rows top first): error_map's image, kErrorBarGap black columns and
// the kErrorBarWidth-wide bar, then a label column.
Image8 numbered_error_map(const Image& error, double max_abs);

// Writes it (atomically, like every image writer); the ImageDescription holds the range.
void write_numbered_error_map_png(const Image& error, const std::filesystem::path& path, double max_abs);

// The bar's labels as written, e.g. "+1.2e-03"; exposed for tests.
std::string bar_label(double value);

}  // namespace vrv
