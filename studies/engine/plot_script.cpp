#include "studies/engine/plot_script.h"

#include <cstdlib>
#include <system_error>

namespace vrv {
namespace fs = std::filesystem;

fs::path find_plot_script(const std::vector<fs::path>& study_dirs) {
  for (const fs::path& d : study_dirs)
    if (std::error_code ec; fs::is_regular_file(d / "engine" / "plot_study.py", ec))
      return d / "engine" / "plot_study.py";
  return "studies/engine/plot_study.py";
}

std::string plot_python() {
  if (const char* env = std::getenv("VRV_PYTHON"); env && *env) return env;
  if (std::error_code ec; fs::exists("/usr/bin/python3", ec)) return "/usr/bin/python3";
  return "python3";
}

}  // namespace vrv
