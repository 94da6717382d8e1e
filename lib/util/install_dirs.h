#pragma once
// Where an installed vrv finds its own files: relative to the program or Python module that is
// running, not the prefix it was configured with, so `cmake --install build --prefix P` can put
// it anywhere (and the tree can be moved).  The relative paths are set by CMake from its install
// directories (cmake/install.cmake): from the program's directory (bin/) and from the Python
// module's (e.g. lib/python3/dist-packages) to the image module's (lib/vrv) and the data's
// (share/vrv).
#include <filesystem>
#include <vector>

namespace vrv {

// The directories of the files running this code, absolute: the object that contains it (the
// program, or the Python module loaded into python3; dladdr), then the program (/proc/self/exe)
// when that is another file.
struct OwnDir {
  std::filesystem::path dir;
  bool program = true;  // false: a shared object (the Python module)
};
std::vector<OwnDir> own_dirs();

enum class InstalledDir { image_module, data };

// The directories, in order, where an installed vrv's image module or data files (plot_study.py)
// are: each own directory itself (the build tree puts things side by side), then the install
// directory relative to it.  Absolute, possibly non-existent.
std::vector<std::filesystem::path> installed_dirs(InstalledDir what);

}  // namespace vrv
