#include "lib/volume/volume_grid.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cmath>
#include <fstream>
#include <stdexcept>
#include <type_traits>
#include <utility>

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

// Grid axis w runs along index axis axis[w] (n[w] samples), mirrored where mirrored[w].
struct GridOrder {
  std::array<int, 3> axis{0, 1, 2};
  GridField::Index3 n{};
  std::array<bool, 3> mirrored{false, false, false};
  bool is_file_order() const {
    return axis == std::array<int, 3>{0, 1, 2} && mirrored == std::array<bool, 3>{false, false, false};
  }
};

// A NaN or infinite sample (float types) refused, naming its index.
void check_samples_finite(const Volume& v, const std::filesystem::path& file) {
  std::visit(
      [&](const auto& s) {
        using T = typename std::decay_t<decltype(s)>::value_type;
        if constexpr (std::is_floating_point_v<T>) {
          for (std::size_t n = 0; n < s.size(); ++n)
            if (!std::isfinite(s[n])) {
              const std::size_t i = n % v.dims[0], j = n / v.dims[0] % v.dims[1], k = n / v.dims[0] / v.dims[1];
              volume_fail(file, "(data)", fmt::format("sample ({}, {}, {}) is {}", i, j, k, static_cast<double>(s[n])));
            }
        }
      },
      v.samples);
}

// Index axes mirrored but not permuted (a NIfTI file in LAS order, say): each mirrored axis's
// rows, planes or slices swapped end for end, in memory order.
template <class Samples>
void mirror_in_place(Samples& s, const std::array<int, 3>& dims, const std::array<bool, 3>& mirrored) {
  const std::size_t nx = dims[0], row = nx, plane = nx * dims[1];
  if (mirrored[0])
    for (std::size_t at = 0; at < s.size(); at += row) std::reverse(s.begin() + at, s.begin() + at + row);
  if (mirrored[1])
    for (std::size_t k = 0; k < static_cast<std::size_t>(dims[2]); ++k)
      for (std::size_t j = 0, last = dims[1] - 1; j < last - j; ++j)
        std::swap_ranges(s.begin() + k * plane + j * row, s.begin() + k * plane + (j + 1) * row,
                         s.begin() + k * plane + (last - j) * row);
  if (mirrored[2])
    for (std::size_t k = 0, last = dims[2] - 1; k < last - k; ++k)
      std::swap_ranges(s.begin() + k * plane, s.begin() + (k + 1) * plane, s.begin() + (last - k) * plane);
}

// The samples put in grid order where they are, in their own type: no second copy of a scan.
// Mirrored axes alone are swapped end for end; otherwise grid node g takes the file's sample at
// source(g), the permutation applied cycle by cycle, one bit a sample marking the nodes placed.
VolumeSamples in_grid_order(VolumeSamples&& samples, const std::array<int, 3>& dims, const GridOrder& order) {
  if (order.is_file_order()) return std::move(samples);
  if (order.axis == std::array<int, 3>{0, 1, 2}) {
    std::visit([&](auto& s) { mirror_in_place(s, dims, order.mirrored); }, samples);
    return std::move(samples);
  }
  const auto source = [&](std::size_t g) {
    const std::size_t g0 = g % order.n[0], g1 = g / order.n[0] % order.n[1], g2 = g / order.n[0] / order.n[1];
    std::array<std::size_t, 3> idx{};
    const std::size_t gw[3] = {g0, g1, g2};
    for (int w = 0; w < 3; ++w) idx[order.axis[w]] = order.mirrored[w] ? order.n[w] - 1 - gw[w] : gw[w];
    return (idx[2] * dims[1] + idx[1]) * dims[0] + idx[0];
  };
  std::visit(
      [&](auto& s) {
        std::vector<bool> placed(s.size(), false);
        for (std::size_t start = 0; start < s.size(); ++start) {
          if (placed[start]) continue;
          const auto first = s[start];
          std::size_t g = start;
          for (std::size_t from = source(g); from != start; g = from, from = source(g)) {
            s[g] = s[from];
            placed[g] = true;
          }
          s[g] = first;
          placed[g] = true;
        }
      },
      samples);
  return std::move(samples);
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

GridField volume_grid(Volume v, const VolumeMapping& mapping, VolumePlacement placement,
                      const Box& scene_box, GridLayout layout, Interpolation interpolation,
                      const std::filesystem::path& file) {
  if (mapping.kind == VolumeValue::rescale && !v.has_rescale)
    volume_fail(file, "value", "rescale: the file's header has no slope and intercept (use raw or a window)");
  SampleMap map;
  map.rescale = mapping.kind != VolumeValue::raw && v.has_rescale;
  map.slope = v.slope, map.intercept = v.intercept;
  map.window = mapping.kind == VolumeValue::window;
  map.lo = mapping.lo, map.hi = mapping.hi;
  const bool header = placement == VolumePlacement::header;
  const Box box = header ? volume_box(v, layout) : scene_box;
  // Grid axis w (world axis w for the header, index axis w for a box), its index axis and whether
  // it runs against it.
  GridOrder order;
  order.n = v.dims;
  if (header)
    for (int w = 0; w < 3; ++w) {
      order.axis[w] = index_axis(v, w);
      order.n[w] = v.dims[order.axis[w]];
      order.mirrored[w] = v.sign[order.axis[w]] < 0;
    }
  check_samples_finite(v, file);
  VolumeSamples samples = in_grid_order(std::move(v.samples), v.dims, order);
  return GridField(box, order.n, layout, interpolation, GridNodes(std::move(samples), map));
}

std::string files_digest(const std::vector<std::filesystem::path>& files) {
  std::string out;
  std::vector<char> chunk(std::size_t{1} << 20);
  for (const auto& f : files) {
    // In chunks: a scan's file is not held a second time beside its samples.
    std::ifstream in(f, std::ios::binary);
    if (!in) volume_fail(f, "(file)", "cannot open to checksum it");
    Crc64 crc;
    while (in) {
      in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
      crc.process_bytes(chunk.data(), static_cast<std::size_t>(in.gcount()));
    }
    if (in.bad()) volume_fail(f, "(file)", "read error while taking its checksum");
    out += fmt::format("{}:{:016x};", f.filename().string(), crc.checksum());
  }
  return out;
}

std::string digest_file_names(std::string_view digest) {
  // Each entry ends ":<16 hex digits>;" (a name may hold ':' or ';' itself).
  constexpr std::size_t kTail = 1 + 16 + 1;
  const auto entry_end = [&](std::size_t at) {
    return at + kTail <= digest.size() && digest[at] == ':' && digest[at + kTail - 1] == ';' &&
           std::all_of(digest.begin() + at + 1, digest.begin() + at + 17,
                       [](char c) { return std::isxdigit(static_cast<unsigned char>(c)); });
  };
  std::string names;
  std::size_t start = 0;
  for (std::size_t at = 0; at < digest.size();) {
    if (!entry_end(at)) {
      ++at;
      continue;
    }
    names += (names.empty() ? "" : ", ") + std::string(digest.substr(start, at - start));
    at += kTail;
    start = at;
  }
  return names;
}

}  // namespace vrv
