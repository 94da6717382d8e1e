#include "studies/engine/plot_script.h"

#include <cstdlib>
#include <system_error>

#include "lib/util/install_dirs.h"

namespace vrv {
namespace fs = std::filesystem;

PlotScript find_plot_script(const std::vector<fs::path>& study_dirs) {
  std::vector<fs::path> candidates;
  for (const fs::path& d : study_dirs) candidates.push_back(d / "engine" / "plot_study.py");
  for (const fs::path& d : installed_dirs(InstalledDir::data)) candidates.push_back(d / "plot_study.py");
  PlotScript script;
  for (const fs::path& c : candidates) {
    if (std::error_code ec; fs::is_regular_file(c, ec)) {
      script.path = c;
      return script;
    }
    script.looked_at += (script.looked_at.empty() ? "" : ", ") + c.string();
  }
  return script;
}

std::string plot_python() {
  if (const char* env = std::getenv("VRV_PYTHON"); env && *env) return env;
  if (std::error_code ec; fs::exists("/usr/bin/python3", ec)) return "/usr/bin/python3";
  return "python3";
}

std::string plot_failure(const PlotScript& script, int status) {
  if (script.path.empty())
    return "the plot script plot_study.py was not found (looked at " + script.looked_at +
           "; set VRV_STUDY_PATH to a directory with engine/plot_study.py)";
  return plot_python() + " " + script.path.string() + " exited with " + std::to_string(status) +
         " (matplotlib: Debian's python3-matplotlib; set VRV_PYTHON)";
}

}  // namespace vrv
