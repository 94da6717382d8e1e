#pragma once
// The plot script, studies/engine/plot_study.py, and the Python that runs it: one lookup for
// `vrv study` and `vrv verify` (study_runner.cpp) and for the Python module's vrv.verify
// (studies/python/module.cpp), which search different directories.  Standard library and the
// install lookup (lib/util/install_dirs.h) only, so the module compiles this file without the
// study engine.
#include <filesystem>
#include <string>
#include <vector>

namespace vrv {

struct PlotScript {
  std::filesystem::path path;  // empty when no copy was found
  std::string looked_at;       // where it looked, comma-separated
};

// engine/plot_study.py under the first of `study_dirs` that has it, else the installed copy,
// <share>/vrv/plot_study.py relative to the running program or Python module.
PlotScript find_plot_script(const std::vector<std::filesystem::path>& study_dirs);

// A Python that has matplotlib: $VRV_PYTHON when set and not empty, else Debian's /usr/bin/python3
// (python3-matplotlib), else python3 from PATH.
std::string plot_python();

// Why a plot was not drawn, one line: the script was not found, or `python script` exited with
// `status` (127: could not be started), which names matplotlib and VRV_PYTHON.
std::string plot_failure(const PlotScript& script, int status);

}  // namespace vrv
