#include "lib/volume/volume_file.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <string>

#include <fmt/format.h>

#include "lib/volume/metaimage_reader.h"
#include "lib/volume/nifti_reader.h"
#include "lib/volume/nrrd_reader.h"
#include "lib/volume/vti_reader.h"

namespace vrv {

Volume read_volume(const std::filesystem::path& file, const VolumeReadOptions& options) {
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) volume_fail(file, "(file)", "is a directory");
  if (!std::ifstream(file, std::ios::binary)) volume_fail(file, "(file)", fmt::format("cannot open: {}", std::strerror(errno)));
  std::string name = file.filename().string();
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::tolower(c); });
  auto ends = [&](std::string_view s) { return name.size() >= s.size() && name.compare(name.size() - s.size(), s.size(), s) == 0; };
  if (ends(".nrrd") || ends(".nhdr")) return read_nrrd(file, options);
  if (ends(".nii") || ends(".nii.gz") || ends(".hdr")) return read_nifti(file, options);
  if (ends(".mha") || ends(".mhd")) return read_metaimage(file, options);
  if (ends(".vti")) return read_vti(file, options);
  volume_fail(file, "(file)", "unknown volume format (expected .nrrd, .nhdr, .nii, .nii.gz, .hdr, .mha, .mhd or .vti)");
}

}  // namespace vrv
