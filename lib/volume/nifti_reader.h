#pragma once
// NIfTI volumes (.nii, .nii.gz, and .hdr/.img pairs; NIfTI-1 and NIfTI-2) through niftilib
// (nifti2_io, which reads both versions).
#include <filesystem>

#include "lib/volume/volume.h"

namespace vrv {

// Placement from the sform when sform_code > 0, else the qform when qform_code > 0 (with its
// qfac, pixdim[0]: ignoring it mirrors the third axis), else the standard's method 1 (pixdim
// spacing, no offset; nibabel instead flips x and centres the grid there).  Rescale: scl_slope
// and scl_inter, where a slope of 0 or a non-finite one means none (as nibabel).  Throws
// VolumeFileError.
Volume read_nifti(const std::filesystem::path& file, const VolumeReadOptions& options = {});

}  // namespace vrv
