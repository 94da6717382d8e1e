#pragma once
// A volume file read by the reader its extension names.
#include <filesystem>

#include "lib/volume/volume.h"

namespace vrv {

// .nrrd/.nhdr (Teem), .nii/.nii.gz/.hdr (niftilib), .mha/.mhd (MetaImage), .vti (VTK XML).
// Throws VolumeFileError for a missing file, an unknown extension or what the reader refuses.
Volume read_volume(const std::filesystem::path& file, const VolumeReadOptions& options = {});

}  // namespace vrv
