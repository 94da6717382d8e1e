#pragma once
// VTK XML image data (.vti): ascii, binary (base64) and appended (raw or base64) arrays, with or
// without vtkZLibDataCompressor; XML through pugixml, base64 through libb64, inflate through zlib.
#include <filesystem>

#include "lib/volume/volume.h"

namespace vrv {

// One Piece covering the WholeExtent, one-component point data (the PointData's Scalars array,
// else its first); Origin, Spacing and Direction (row-major, VTK 9) placed as VTK does: the
// first sample of extent (x0, y0, z0) at Origin + Direction diag(Spacing) (x0, y0, z0).
// Cell data, several pieces and the LZ4/LZMA compressors are refused.  Throws VolumeFileError.
Volume read_vti(const std::filesystem::path& file, const VolumeReadOptions& options = {});

}  // namespace vrv
