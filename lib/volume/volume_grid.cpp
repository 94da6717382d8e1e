#include "lib/volume/volume_grid.h"

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "lib/util/checksum.h"

namespace vrv {
namespace {

// Index axis that runs along world axis w.
int index_axis(const Volume& v, int w) {
  for (int a = 0; a < 3; ++a)
    if (v.axis[a] == w) return a;
  return w;  // unreachable: axis is a permutation
}

}  // namespace

Box volume_box(const Volume& v, GridLayout layout) {
  Box box;
  for (int w = 0; w < 3; ++w) {
    const int a = index_axis(v, w);
    if (layout == GridLayout::node && v.dims[a] < 2)
      throw std::invalid_argument(fmt::format(
          "one sample along index axis {}: node layout needs two (layout = \"cell\" gives it a voxel)", a));
    // The header's origin is exact on its own side; the far side is (n - 1) steps away.
    const double far = (v.dims[a] - 1) * v.spacing[a];
    box.min[w] = v.sign[a] > 0 ? v.origin[w] : v.origin[w] - far;
    box.max[w] = v.sign[a] > 0 ? v.origin[w] + far : v.origin[w];
    if (layout == GridLayout::cell) {
      box.min[w] -= v.spacing[a] / 2;
      box.max[w] += v.spacing[a] / 2;
    }
  }
  return box;
}

GridField volume_grid(const Volume& v, const VolumeMapping& mapping, VolumePlacement placement,
                      const Box& scene_box, GridLayout layout, Interpolation interpolation,
                      const std::filesystem::path& file) {
  if (mapping.kind == VolumeValue::rescale && !v.has_rescale)
    volume_fail(file, "value", "rescale: the file's header has no slope and intercept (use raw or a window)");
  const bool rescale = mapping.kind != VolumeValue::raw && v.has_rescale;
  auto value = [&](double s) {
    const double x = rescale ? v.slope * s + v.intercept : s;
    if (mapping.kind != VolumeValue::window) return x;
    return std::clamp((x - mapping.lo) / (mapping.hi - mapping.lo), 0.0, 1.0);
  };
  const bool header = placement == VolumePlacement::header;
  const Box box = header ? volume_box(v, layout) : scene_box;
  // Grid axis w (world axis w for the header, index axis w for a box) and its index axis.
  std::array<int, 3> a{0, 1, 2};
  GridField::Index3 n = v.dims;
  if (header)
    for (int w = 0; w < 3; ++w) {
      a[w] = index_axis(v, w);
      n[w] = v.dims[a[w]];
    }
  std::vector<double> values(static_cast<std::size_t>(n[0]) * n[1] * n[2]);
  std::size_t out = 0;
  std::array<int, 3> g{};
  for (g[2] = 0; g[2] < n[2]; ++g[2])
    for (g[1] = 0; g[1] < n[1]; ++g[1])
      for (g[0] = 0; g[0] < n[0]; ++g[0]) {
        std::array<int, 3> idx{};
        for (int w = 0; w < 3; ++w)
          idx[a[w]] = header && v.sign[a[w]] < 0 ? n[w] - 1 - g[w] : g[w];
        const double s = v.sample(idx[0], idx[1], idx[2]);
        if (!std::isfinite(s))
          volume_fail(file, "(data)", fmt::format("sample ({}, {}, {}) is {}", idx[0], idx[1], idx[2], s));
        values[out++] = value(s);
      }
  return GridField(box, n, layout, interpolation, std::move(values));
}

std::string files_digest(const std::vector<std::filesystem::path>& files) {
  std::string out;
  for (const auto& f : files) out += fmt::format("{}:{};", f.filename().string(), crc64_hex(read_file_bytes(f, SIZE_MAX)));
  return out;
}

}  // namespace vrv
