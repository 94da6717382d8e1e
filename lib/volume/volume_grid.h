#pragma once
// A volume as the scene's field: its samples mapped to values and placed in the world as a
// GridField (node or cell layout, trilinear or nearest).
#include <filesystem>
#include <string>
#include <string_view>

#include "lib/geometry.h"
#include "lib/grid_field.h"
#include "lib/util/enum_names.h"
#include "lib/volume/volume.h"

namespace vrv {

// raw: the stored number; rescale: slope * stored + intercept from the header (refused for a
// file without one); window: (v - lo) / (hi - lo) clamped to [0, 1], v rescaled where the
// header has a rescale (data units), else raw.  Applied to the samples (the nodes), before
// interpolation, as a renderer's texture holds them.
enum class VolumeValue { raw, rescale, window };
struct VolumeMapping {
  VolumeValue kind = VolumeValue::raw;
  double lo = 0, hi = 1;  // window only, lo < hi
};

// header: the header's spacing, origin and axis-aligned directions (a mirrored or permuted
// index axis is reordered to ascending world coordinates); box: plain index order (i along x)
// filling the scene's box.
enum class VolumePlacement { header, box };
inline constexpr NameTable<VolumePlacement, 2> kVolumePlacementNames{
    {{VolumePlacement::header, "header"}, {VolumePlacement::box, "box"}}};  // as scene files name them
static_assert(names_complete(kVolumePlacementNames));

// Where the header places the samples: node layout, the first and last sample on the box
// faces; cell layout, the box half a voxel larger on every side (renderers that treat point
// data as cells).  Node layout needs two samples per axis (std::invalid_argument).
Box volume_box(const Volume& v, GridLayout layout);

// The grid holds the samples in their own type (lib/grid_nodes.h), moved from `v`: as they are
// when the grid's node order is the file's (box placement, or a header with unmirrored index axes
// along x, y, z), else put in grid order where they are (mirrored axes swapped end for end;
// permuted ones cycle by cycle, one bit a sample beside them).  Throws VolumeFileError naming
// `file` for a non-finite sample or a rescale the file lacks, and std::invalid_argument for a
// grid GridField refuses (one sample on an axis in node layout).
GridField volume_grid(Volume v, const VolumeMapping& mapping, VolumePlacement placement,
                      const Box& scene_box, GridLayout layout, Interpolation interpolation,
                      const std::filesystem::path& file);

// CRC-64 of each file's bytes (lib/util/checksum.h), "name:crc;" per file: what the scene hash
// adds for a field read from files, so that a changed file behind the same scene changes it.
std::string files_digest(const std::vector<std::filesystem::path>& files);
// The file names a files_digest holds, comma-separated (for messages).
std::string digest_file_names(std::string_view digest);

}  // namespace vrv
