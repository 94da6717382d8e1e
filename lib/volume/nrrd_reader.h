#pragma once
// NRRD volumes (.nrrd, and .nhdr with detached data; raw, gzip and the other encodings Teem
// reads) through Teem's nrrdLoad.
#include <filesystem>

#include "lib/volume/volume.h"

namespace vrv {

// Three axes of one of the eight scalar types; geometry from "space directions" and
// "space origin" (the file's own space, e.g. RAS or LPS, not converted), else from "spacings"
// (1 when absent) with the first sample at 0.  Throws VolumeFileError.
Volume read_nrrd(const std::filesystem::path& file, const VolumeReadOptions& options = {});

}  // namespace vrv
