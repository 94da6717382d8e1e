#pragma once
// MetaImage volumes (.mha with the data in the file, .mhd with a detached data file; raw or
// zlib-compressed), parsed here: Debian has no small MetaIO library (ITK, which has one, is far
// too large a dependency for a key = value header), and zlib inflates the data.
#include <filesystem>

#include "lib/volume/volume.h"

namespace vrv {

// NDims = 3, ElementNumberOfChannels = 1, ElementType MET_UCHAR ... MET_DOUBLE; geometry from
// ElementSpacing (or ElementSize), Offset (or Position, Origin) and TransformMatrix (or
// Rotation, Orientation; triple a is index axis a's direction, as ITK reads it).  Data:
// ElementDataFile = LOCAL or a file name (HeaderSize bytes skipped, -1: the data end the file);
// LIST and numbered patterns are refused.  Throws VolumeFileError.
Volume read_metaimage(const std::filesystem::path& file, const VolumeReadOptions& options = {});

}  // namespace vrv
