// vrv study: runs a study (studies/NAME/NAME.toml or a path) and writes its tables into
// OUT/NAME/.  The engine is studies/engine/study_runner.h; this is the command line around it.
#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "lib/io/study_file.h"
#include "studies/cli/commands.h"
#include "studies/engine/study_runner.h"

namespace vrv::cli {
namespace {

struct StudyOptions {
  std::string study;
  bool list = false;
  bool all = false;
  StudyRunOptions run;
};

int run_study(const StudyOptions& opt) {
  if (opt.list) {
    if (!opt.study.empty()) throw std::invalid_argument("--list: takes no study name");
    for (const auto& [name, path] : find_studies()) {
      std::string desc;
      try {
        desc = load_study_file(path).description;
      } catch (const std::exception& e) {
        desc = std::string("(invalid: ") + e.what() + ")";
      }
      std::cout << fmt::format("{}\t{}\t{}\n", name, path.string(), desc);
    }
    return 0;
  }
  if (opt.run.threads < 0)
    throw std::invalid_argument(fmt::format("--threads: must not be negative, got {}", opt.run.threads));
  if (opt.all) {
    if (!opt.study.empty()) throw std::invalid_argument("--all: takes no study name");
    // Every study file is checked before any runs, so a bad file costs no time.
    std::vector<LoadedStudy> studies;
    for (const auto& [name, path] : find_studies()) {
      try {
        studies.push_back(load_study_file(path));
      } catch (const StudyFileError& e) {
        throw std::invalid_argument(e.what());
      }
    }
    int rc = 0;
    for (const LoadedStudy& s : studies) rc = std::max(rc, run_study_job(s, opt.run));
    return rc;
  }
  if (opt.study.empty())
    throw std::invalid_argument("study: give a study NAME or FILE.toml (or --all, --list)");
  LoadedStudy study;
  try {
    study = load_study_file(resolve_study(opt.study));
  } catch (const StudyFileError& e) {
    throw std::invalid_argument(e.what());
  }
  return run_study_job(study, opt.run);
}

}  // namespace

void add_study_command(CLI::App& app) {
  auto opt = std::make_shared<StudyOptions>();
  CLI::App* cmd = app.add_subcommand(
      "study", "Run a study (studies/NAME/NAME.toml or FILE.toml) and write its tables, images and plots");
  cmd->footer(
      "Studies are looked up as NAME/NAME.toml in ./studies, <vrv's directory>/../studies, "
      "$VRV_STUDY_PATH and the source tree vrv was built from.\n"
      "Writes OUT/NAME/: the study's own tables (CSV, Markdown, LaTeX), images and plots, plus "
      "checks.{csv,md,tex} and meta.json. stdout: one JSON line {\"study\", \"out\", \"pass\"}; "
      "exit 1 when a check fails or the plots cannot be drawn, 2 for a bad study file.\n"
      "See docs/studies.md.");
  cmd->add_option("study", opt->study, "Study NAME (studies/NAME/NAME.toml) or FILE.toml");
  cmd->add_flag("--list", opt->list, "List the studies found");
  cmd->add_flag("--all", opt->all, "Run every study found, in name order (results/ is --all --out results)");
  cmd->add_flag("--quick", opt->run.quick, "Fewer rays (the study's quick_count)");
  cmd->add_option("--out", opt->run.out, "Output directory (results go into OUT/NAME/)")->capture_default_str();
  cmd->add_option("--threads", opt->run.threads, "Threads (default: all cores); results do not depend on it");
  cmd->add_flag("--quiet", opt->run.quiet, "No progress bar or summary on stderr");
  cmd->add_flag("--no-plots", opt->run.no_plots, "Do not run the plot script (studies/engine/plot_study.py)");
  cmd->callback([opt] {
    const int rc = run_study(*opt);
    if (rc != 0) std::exit(rc);
  });
}

}  // namespace vrv::cli
