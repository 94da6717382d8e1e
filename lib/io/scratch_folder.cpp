#include "lib/io/scratch_folder.h"

#include <stdlib.h>  // mkdtemp

#include <stdexcept>

#include <fmt/format.h>

namespace vrv {

namespace fs = std::filesystem;

ScratchFolder::ScratchFolder(const std::string& prefix, const std::string& purpose) {
  std::string pattern = (fs::temp_directory_path() / (prefix + "-XXXXXX")).string();
  if (!mkdtemp(pattern.data()))
    throw std::runtime_error(fmt::format("{}: cannot create a temporary folder for {}", pattern, purpose));
  dir_ = pattern;
}

ScratchFolder::~ScratchFolder() {
  std::error_code ec;
  fs::remove_all(dir_, ec);
}

}  // namespace vrv
