// vrv study: runs a study described by a TOML file (studies/NAME.toml or a path) and writes its
// tables into OUT/NAME/.  The engine is lib/study.h; this is the command line around it.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <toml++/toml.h>
#include <nlohmann/json.hpp>

#include "lib/parallel.h"
#include "lib/study_file.h"
#include "lib/io/error_line.h"
#include "studies/engine/checkpoint.h"
#include "studies/engine/interrupt.h"
#include "studies/engine/memory_budget.h"
#include "studies/engine/study_loader.h"
#include "studies/engine/study_runner.h"
#include "studies/study_driver.h"
#include "studies/commands.h"

namespace vrv::cli {
namespace {

namespace fs = std::filesystem;

struct StudyOptions {
  std::string study;
  bool list = false;
  bool quick = false;
  std::string out = "results";
  int threads = 0;
  bool quiet = false;
  bool no_plots = false;
  bool all = false;
  bool resume = false;
  double max_memory_gib = 0;  // 0: default_memory_limit()
};

StudyLoadOptions load_options(const StudyOptions& opt) {
  return {.memory_limit = opt.max_memory_gib * double(1 << 30)};
}

LoadedStudy load(const fs::path& path, const StudyOptions& opt) { return load_study_file(path, load_options(opt)); }

// The plot script (studies/plot_study.py) next to the study files, and a Python that has
// matplotlib: $VRV_PYTHON, else Debian's /usr/bin/python3 (python3-matplotlib), else python3.
fs::path plot_script();
std::string python();

// Where studies/NAME.toml are looked for, in order: ./studies, <executable dir>/../studies,
// $VRV_STUDY_PATH, and the source tree this file was compiled from (__FILE__'s directory).
std::vector<fs::path> study_dirs() {
  std::vector<fs::path> dirs{fs::path("studies")};
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) dirs.push_back(exe.parent_path().parent_path() / "studies");
  if (const char* env = std::getenv("VRV_STUDY_PATH"); env && *env) dirs.emplace_back(env);
  const fs::path here(__FILE__);
  if (here.is_absolute()) dirs.push_back(here.parent_path());
  return dirs;
}

// Study files (*.toml with kind = ...) found in the search directories, first one wins per name.
std::vector<std::pair<std::string, fs::path>> find_studies() {
  std::vector<std::pair<std::string, fs::path>> found;
  std::set<std::string> names;
  for (const fs::path& dir : study_dirs()) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) continue;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir, ec))
      if (e.path().extension() == ".toml") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const fs::path& f : files)
      if (names.insert(f.stem().string()).second) found.emplace_back(f.stem().string(), f);
  }
  return found;
}

fs::path resolve_study(const std::string& arg) {
  const fs::path p(arg);
  if (p.extension() == ".toml" || arg.find('/') != std::string::npos) return p;
  for (const auto& [name, path] : find_studies())
    if (name == arg) return path;
  std::string where;
  for (const fs::path& d : study_dirs()) where += (where.empty() ? "" : ", ") + d.string();
  throw std::invalid_argument(
      fmt::format("study: no study named '{}' (looked for {}.toml in {}; see vrv study --list)", arg,
                  arg, where));
}

int run_one(const LoadedStudy& study, const StudyOptions& opt);

// --all: two files with one `name` would overwrite each other's folder; together, the studies'
// grids are held at once (each driver builds them as it reads its file).
void check_all(const std::vector<LoadedStudy>& studies, const StudyOptions& opt) {
  std::map<std::string, std::string> seen;  // name -> file
  double bytes = 0;
  const double limit = opt.max_memory_gib > 0 ? opt.max_memory_gib * double(1 << 30) : default_memory_limit();
  for (const LoadedStudy& s : studies) {
    if (const auto [it, fresh] = seen.emplace(s.name, s.source); !fresh)
      throw std::invalid_argument(error_line(s.source, "name", fmt::format(
          "'{}' is also the name of {} (each study writes its own folder OUT/NAME)", s.name, it->second)));
    bytes += s.memory_bytes;
    if (bytes > limit)
      throw std::invalid_argument(error_line(s.source, "(memory)", fmt::format(
          "with the studies before it, --all needs about {} for grids, more than the limit of {} "
          "(raise it with --max-memory GIB, or run the studies one by one)", gibibytes(bytes), gibibytes(limit))));
  }
}

int run_study(const StudyOptions& opt) {
  if (opt.list) {
    if (!opt.study.empty()) throw std::invalid_argument("--list: takes no study name");
    for (const auto& [name, path] : find_studies()) {
      std::string desc;
      try {
        desc = load(path, opt).description;
      } catch (const std::exception& e) {
        desc = std::string("(invalid: ") + e.what() + ")";
      }
      std::cout << fmt::format("{}\t{}\t{}\n", name, path.string(), desc);
    }
    return 0;
  }
  if (opt.threads < 0) throw std::invalid_argument(fmt::format("--threads: must not be negative, got {}", opt.threads));
  if (opt.max_memory_gib < 0 || !std::isfinite(opt.max_memory_gib))
    throw std::invalid_argument(fmt::format("--max-memory: must be a positive number of GiB, got {}", opt.max_memory_gib));
  // Before any worker thread exists: SIGINT/SIGTERM go to the watcher (studies/engine/interrupt.h).
  const InterruptGuard interrupts;
  if (opt.all) {
    if (!opt.study.empty()) throw std::invalid_argument("--all: takes no study name");
    if (opt.resume) throw std::invalid_argument("--resume: give the study NAME to resume, not --all");
    // Every study file is checked before any runs, so a bad file costs no time.
    std::vector<LoadedStudy> studies;
    for (const auto& [name, path] : find_studies()) {
      try {
        studies.push_back(load(path, opt));
      } catch (const StudyFileError& e) {
        throw std::invalid_argument(e.what());
      }
    }
    check_all(studies, opt);
    int rc = 0;
    for (const LoadedStudy& s : studies) rc = std::max(rc, run_one(s, opt));
    return rc;
  }
  if (opt.study.empty())
    throw std::invalid_argument("study: give a study NAME or FILE.toml (or --all, --list)");
  LoadedStudy study;
  try {
    study = load(resolve_study(opt.study), opt);
  } catch (const StudyFileError& e) {
    throw std::invalid_argument(e.what());
  }
  return run_one(study, opt);
}

// Runs one study into OUT/NAME (studies/engine/study_runner.h); 0 when every check passes and
// the plots were drawn.
int run_one(const LoadedStudy& study, const StudyOptions& opt) {
  StudyRunOptions run;
  run.out = opt.out;
  run.quick = opt.quick;
  run.progress = !opt.quiet;
  run.quiet = opt.quiet;
  run.plots = !opt.no_plots;
  run.resume = opt.resume;
  run.threads = opt.threads;
  run.python = python();
  run.plot_script = plot_script();
  const ThreadLimit limit(opt.threads);
  try {
    return run_loaded_study(study, run);
  } catch (const StudyResumeError& e) {
    throw std::invalid_argument(e.what());
  }
}

fs::path plot_script() {
  for (const fs::path& d : study_dirs())
    if (std::error_code ec; fs::is_regular_file(d / "plot_study.py", ec)) return d / "plot_study.py";
  return "studies/plot_study.py";
}

std::string python() {
  if (const char* env = std::getenv("VRV_PYTHON"); env && *env) return env;
  if (std::error_code ec; fs::exists("/usr/bin/python3", ec)) return "/usr/bin/python3";
  return "python3";
}

}  // namespace

void add_study_command(CLI::App& app) {
  auto opt = std::make_shared<StudyOptions>();
  CLI::App* cmd = app.add_subcommand(
      "study", "Run a study (TOML data: studies/NAME.toml or FILE.toml) and write its tables");
  cmd->footer(
      "Studies are looked up as studies/NAME.toml in ./studies, <vrv's directory>/../studies, "
      "$VRV_STUDY_PATH and the source tree vrv was built from.\n"
      "Writes OUT/NAME/: the study's own tables (CSV, Markdown, LaTeX), images and plots, plus "
      "checks.{csv,md,tex} and meta.json. stdout: one JSON line {\"study\", \"out\", \"pass\"}; "
      "exit 1 when a check fails or the plots cannot be drawn, 2 for a bad study file, 130/143 when "
      "stopped by SIGINT/SIGTERM.\n"
      "The run is written to OUT/.NAME.partial/ and replaces OUT/NAME/ in one step when it is "
      "complete; an interrupted run leaves OUT/NAME/ as it was, and --resume continues it.\n"
      "See docs/studies.md and docs/robustness.md.");
  cmd->add_option("study", opt->study, "Study NAME (studies/NAME.toml) or FILE.toml");
  cmd->add_flag("--list", opt->list, "List the studies found");
  cmd->add_flag("--all", opt->all, "Run every study found, in name order (results/ is --all --out results)");
  cmd->add_flag("--quick", opt->quick, "Fewer rays (the study's quick_count)");
  cmd->add_option("--out", opt->out, "Output directory (results go into OUT/NAME/)")->capture_default_str();
  cmd->add_option("--threads", opt->threads, "Threads (default: all cores); results do not depend on it");
  cmd->add_flag("--quiet", opt->quiet, "No progress bar or summary on stderr");
  cmd->add_flag("--no-plots", opt->no_plots, "Do not run the plot script (studies/plot_study.py)");
  cmd->add_flag("--resume", opt->resume,
                "Continue an interrupted run of this study from its checkpoints (OUT/.NAME.partial)");
  cmd->add_option("--max-memory", opt->max_memory_gib,
                  "GiB the study's grids may take (default: 3/4 of this machine's memory)");
  cmd->callback([opt] {
    const int rc = run_study(*opt);
    if (rc != 0) std::exit(rc);
  });
}

}  // namespace vrv::cli
