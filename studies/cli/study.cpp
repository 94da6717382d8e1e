// vrv study: runs a study (studies/NAME/NAME.toml or a path) and writes its tables into
// OUT/NAME/.  The engine is studies/engine/study_runner.h; this is the command line around it.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "lib/io/error_line.h"
#include "lib/study_file.h"
#include "lib/util/ranks.h"
#include "studies/cli/cli_support.h"
#include "studies/cli/commands.h"
#include "studies/cli/memory_limit.h"
#include "studies/engine/checkpoint.h"
#include "studies/engine/interrupt.h"
#include "studies/engine/memory_budget.h"
#include "studies/engine/study_loader.h"
#include "studies/engine/study_runner.h"
#include "studies/engine/study_work.h"

namespace vrv::cli {
namespace {

struct StudyOptions {
  std::string study;
  bool list = false;
  bool estimate = false;  // print the estimates, run nothing
  bool all = false;
  std::optional<double> max_memory_gib;  // not given: default_memory_limit()
  double max_work = kDefaultStudyWorkLimit;  // field evaluations (studies/engine/study_work.h)
  StudyRunOptions run;
};

double memory_limit(const StudyOptions& opt) { return memory_limit_bytes(opt.max_memory_gib); }

LoadedStudy load(const std::filesystem::path& path, const StudyOptions& opt) {
  return load_study_file(path, {.memory_limit = memory_limit(opt)});
}

// The study, checked against the work limit for the variant it will run as.
LoadedStudy load_to_run(const std::filesystem::path& path, const StudyOptions& opt) {
  LoadedStudy study = load(path, opt);
  if (!opt.estimate) check_study_work(study, opt.run.quick, opt.max_work);
  return study;
}

// --estimate: one JSON line per study, what it would cost; nothing runs.
void print_estimate(const LoadedStudy& study, const StudyOptions& opt) {
  const StudyWork work = estimate_study_work(study, opt.run.quick);
  nlohmann::ordered_json line;
  line["study"] = study.name;
  line["quick"] = opt.run.quick;
  line["memory_bytes"] = study.memory_bytes;
  line["evaluations"] = work.evaluations();
  line["within_limits"] = work.evaluations() <= opt.max_work;
  line["parts"] = to_json(work)["parts"];
  std::cout << line.dump() << '\n';
}

// --all: two files with one `name` would overwrite each other's folder; together, the studies'
// grids are held at once (each driver builds them as it reads its file).
void check_all(const std::vector<LoadedStudy>& studies, const StudyOptions& opt) {
  std::map<std::string, std::string> seen;  // name -> file
  double bytes = 0;
  const double limit = memory_limit(opt);
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

int run_one(const LoadedStudy& study, const StudyOptions& opt) {
  try {
    return run_study_job(study, opt.run);
  } catch (const StudyResumeError& e) {
    throw std::invalid_argument(e.what());
  }
}

int run_study(const StudyOptions& opt) {
  memory_limit(opt);  // --max-memory checked before any file is read, --list's too
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
  if (opt.run.threads < 0)
    throw std::invalid_argument(fmt::format("--threads: must not be negative, got {}", opt.run.threads));
  if (!(opt.max_work > 0) || !std::isfinite(opt.max_work))
    throw std::invalid_argument(fmt::format("--max-work: must be a positive number of field evaluations, got {}", opt.max_work));
  if (opt.run.resume && rank_count() > 1)
    throw std::invalid_argument(fmt::format(
        "--resume: {} MPI ranks keep no checkpoints; resume as one process, or run again (docs/distributed.md)",
        rank_count()));
  // Before any worker thread exists: SIGINT/SIGTERM go to the watcher (studies/engine/interrupt.h).
  const InterruptGuard interrupts;
  if (opt.all) {
    if (!opt.study.empty()) throw std::invalid_argument("--all: takes no study name");
    if (opt.run.resume) throw std::invalid_argument("--resume: give the study NAME to resume, not --all");
    // Every study file is checked before any runs, so a bad file costs no time.
    std::vector<LoadedStudy> studies;
    for (const auto& [name, path] : find_studies()) {
      try {
        studies.push_back(load_to_run(path, opt));
      } catch (const StudyFileError& e) {
        throw std::invalid_argument(e.what());
      }
    }
    check_all(studies, opt);
    if (opt.estimate) {
      for (const LoadedStudy& s : studies) print_estimate(s, opt);
      return 0;
    }
    int rc = 0;
    for (const LoadedStudy& s : studies) rc = std::max(rc, run_one(s, opt));
    return rc;
  }
  if (opt.study.empty())
    throw std::invalid_argument("study: give a study NAME or FILE.toml (or --all, --list)");
  LoadedStudy study;
  try {
    study = load_to_run(resolve_study(opt.study), opt);
  } catch (const StudyFileError& e) {
    throw std::invalid_argument(e.what());
  }
  if (opt.estimate) {
    print_estimate(study, opt);
    return 0;
  }
  return run_one(study, opt);
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
      "exit 1 when a check fails or the plots cannot be drawn, 2 for a bad study file or one above --max-memory or --max-work, 130/143 when "
      "stopped by SIGINT/SIGTERM.\n"
      "The run is written to OUT/.NAME.partial/ and replaces OUT/NAME/ in one step when it is "
      "complete; an interrupted run leaves OUT/NAME/ as it was, and --resume continues it.\n"
      "See docs/studies.md and docs/robustness.md.");
  cmd->add_option("study", opt->study, "Study NAME (studies/NAME/NAME.toml) or FILE.toml");
  cmd->add_flag("--list", opt->list, "List the studies found");
  cmd->add_flag("--all", opt->all, "Run every study found, in name order (results/ is --all --out results)");
  cmd->add_flag("--quick", opt->run.quick, "Fewer rays (the study's quick_count)");
  cmd->add_option("--out", opt->run.out, "Output directory (results go into OUT/NAME/)")->capture_default_str();
  cmd->add_option("--threads", opt->run.threads, "Threads (default: all cores); results do not depend on it");
  cmd->add_flag("--quiet", opt->run.quiet, "No progress bar or summary on stderr");
  cmd->add_flag("--no-plots", opt->run.no_plots, "Do not run the plot script (studies/engine/plot_study.py)");
  cmd->add_flag("--resume", opt->run.resume,
                "Continue an interrupted run of this study from its checkpoints (OUT/.NAME.partial)");
  cmd->add_option("--max-memory", opt->max_memory_gib,
                  "GiB the study's grids may take (default: 3/4 of this machine's memory)");
  cmd->add_option("--max-work", opt->max_work,
                  "Field evaluations the study may take, estimated from its file before it runs "
                  "(discrete samples and the reference's; see docs/robustness.md)")
      ->capture_default_str();
  cmd->add_flag("--estimate", opt->estimate,
                "Print the study's estimated memory and field evaluations, per part, as one JSON line; run nothing");
  cmd->callback([opt] {
    const int rc = run_study(*opt);
    if (rc != 0) throw CommandFailed(rc, "");  // main checks standard output before it exits
  });
}

}  // namespace vrv::cli
