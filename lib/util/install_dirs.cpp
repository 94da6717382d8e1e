#include "lib/util/install_dirs.h"

#include <dlfcn.h>

#include <algorithm>
#include <string>
#include <system_error>

// Set by CMake (cmake/install.cmake): relative paths between install directories.
#ifndef VRV_BIN_TO_IMAGE_MODULE
#define VRV_BIN_TO_IMAGE_MODULE "../lib/vrv"
#endif
#ifndef VRV_BIN_TO_DATA
#define VRV_BIN_TO_DATA "../share/vrv"
#endif
#ifndef VRV_PYTHON_TO_IMAGE_MODULE
#define VRV_PYTHON_TO_IMAGE_MODULE "../../vrv"
#endif
#ifndef VRV_PYTHON_TO_DATA
#define VRV_PYTHON_TO_DATA "../../../share/vrv"
#endif

namespace vrv {
namespace fs = std::filesystem;

std::vector<OwnDir> own_dirs() {
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) exe.clear();
  fs::path object;
  Dl_info info{};
  // dladdr names a shared object by the path it was loaded from, the main program as it was
  // started (perhaps without a slash): that one is /proc/self/exe.
  if (dladdr(reinterpret_cast<const void*>(&own_dirs), &info) && info.dli_fname &&
      std::string(info.dli_fname).find('/') != std::string::npos) {
    object = fs::weakly_canonical(fs::absolute(info.dli_fname, ec), ec);
    if (ec) object.clear();
  }
  std::vector<OwnDir> dirs;
  if (!object.empty() && object != exe) dirs.push_back({object.parent_path(), false});
  if (!exe.empty()) dirs.push_back({exe.parent_path(), true});
  return dirs;
}

std::vector<fs::path> installed_dirs(InstalledDir what) {
  const bool module = what == InstalledDir::image_module;
  std::vector<fs::path> out;
  for (const OwnDir& own : own_dirs()) {
    const char* rel = own.program ? (module ? VRV_BIN_TO_IMAGE_MODULE : VRV_BIN_TO_DATA)
                                  : (module ? VRV_PYTHON_TO_IMAGE_MODULE : VRV_PYTHON_TO_DATA);
    for (const fs::path& p : {own.dir, (own.dir / rel).lexically_normal()})
      if (std::find(out.begin(), out.end(), p) == out.end()) out.push_back(p);
  }
  return out;
}

}  // namespace vrv
