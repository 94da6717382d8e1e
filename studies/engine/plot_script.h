#pragma once
// The plot script, studies/engine/plot_study.py, and the Python that runs it: one lookup for
// `vrv study` and `vrv verify` (study_runner.cpp) and for the Python module's vrv.verify
// (studies/python/module.cpp), which search different directories.  Standard library only, so the
// module compiles this file without the study engine.
#include <filesystem>
#include <string>
#include <vector>

namespace vrv {

// engine/plot_study.py under the first of `study_dirs` that has it; else the relative path
// studies/engine/plot_study.py (which then fails to run, and the caller reports it).
std::filesystem::path find_plot_script(const std::vector<std::filesystem::path>& study_dirs);

// A Python that has matplotlib: $VRV_PYTHON when set and not empty, else Debian's /usr/bin/python3
// (python3-matplotlib), else python3 from PATH.
std::string plot_python();

}  // namespace vrv
