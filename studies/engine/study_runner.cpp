#include "studies/engine/study_runner.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <mutex>
#include <optional>
#include <set>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <toml++/toml.h>
#include <nlohmann/json.hpp>

#include "lib/io/atomic_file.h"
#include "lib/io/run_metadata.h"
#include "lib/io/scratch_folder.h"
#include "lib/study_file.h"
#include "lib/util/parallel.h"
#include "lib/util/ranks.h"

#include "studies/engine/checkpoint.h"
#include "studies/engine/interrupt.h"
#include "studies/engine/plot_script.h"
#include "studies/engine/reference_audit.h"
#include "studies/engine/study_work.h"
#include "studies/engine/staging.h"

namespace vrv {
namespace {

namespace fs = std::filesystem;

// One line naming the failed checks.
std::string failures(const std::vector<StudyCheck>& checks) {
  std::string out;
  for (const StudyCheck& c : checks)
    if (!c.pass)
      out += fmt::format("{}{} (value {:.4g}, bound {:.4g})", out.empty() ? "" : ", ", c.name,
                         c.value, c.bound);
  return out;
}

// Runs the plot script (plot_script.h) on `dir` (which has plots.json) in its own process group,
// which an interruption ends; its messages go to stderr.  Its exit status (127: not started, or
// no script).
int draw_plots(const fs::path& dir, const PlotScript& found) {
  if (found.path.empty()) return 127;
  const std::string py = plot_python(), script = found.path.string();
  const std::string where = dir.string();
  const pid_t pid = fork();
  if (pid < 0) return 127;
  if (pid == 0) {
    ::setpgid(0, 0);
    unblock_stop_signals();
    const char* argv[] = {py.c_str(), script.c_str(), where.c_str(), nullptr};
    execvp(argv[0], const_cast<char* const*>(argv));
    _exit(127);
  }
  ::setpgid(pid, pid);  // also here, so the group exists before an interruption can aim at it
  set_interrupt_child(pid);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) {
      status = 127 << 8;
      break;
    }
  set_interrupt_child(0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

nlohmann::json meta_json(const LoadedStudy& study, const StudyRunOptions& opt, const StudyOutcome& outcome,
                         double seconds, bool pass, const std::string& plots) {
  nlohmann::ordered_json parameters;
  parameters["study"] = study.name;
  parameters["kind"] = study.kind;
  parameters["file"] = study.source;
  parameters["description"] = study.description;
  parameters["quick"] = opt.quick;
  parameters["threads"] = opt.threads;  // recorded only; no number depends on it
  parameters["file_text"] = study.text;
  parameters["run"] = outcome.parameters;
  nlohmann::json meta = run_metadata(nlohmann::json::parse(parameters.dump()), seconds);
  meta["pass"] = pass;
  meta["plots"] = plots;
  meta["summary"] = outcome.summary;
  // The estimate the run was admitted on (study_work.h) and the rate it ran at on this machine:
  // what calibrates --max-work (docs/robustness.md, "Work limits").
  if (study.work) {
    nlohmann::json work = to_json(study.work(opt.quick));
    work["per_second"] = seconds > 0 ? work["evaluations"].get<double>() / seconds : 0.0;
    meta["work_estimate"] = work;
  }
  nlohmann::json checks = nlohmann::json::array();
  for (const StudyCheck& c : outcome.checks)
    checks.push_back({{"name", c.name},
                      {"value", std::isfinite(c.value) ? nlohmann::json(c.value) : nlohmann::json()},
                      {"bound", std::isfinite(c.bound) ? nlohmann::json(c.bound) : nlohmann::json()},
                      {"pass", c.pass},
                      {"kind", check_kind_name(c.kind)},
                      {"detail", c.detail}});
  meta["checks"] = checks;
  return meta;
}

}  // namespace

std::vector<fs::path> study_dirs() {
  std::vector<fs::path> dirs{fs::path("studies")};
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) dirs.push_back(exe.parent_path().parent_path() / "studies");
  if (const char* env = std::getenv("VRV_STUDY_PATH"); env && *env) dirs.emplace_back(env);
  const fs::path here(__FILE__);  // studies/engine/study_runner.cpp
  if (here.is_absolute()) dirs.push_back(here.parent_path().parent_path());
  return dirs;
}

std::vector<std::pair<std::string, fs::path>> find_studies() {
  std::vector<std::pair<std::string, fs::path>> found;
  std::set<std::string> names;
  for (const fs::path& dir : study_dirs()) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) continue;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
      const fs::path file = e.path() / (e.path().filename().string() + ".toml");
      if (std::error_code fec; fs::is_regular_file(file, fec)) files.push_back(file);
    }
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
      fmt::format("study: no study named '{}' (looked for {}/{}.toml in {}; see vrv study --list)", arg,
                  arg, arg, where));
}

namespace {

// The study's job; a refusal of a non-finite value (a table's column) after --resume reused one
// names the checkpoint that held it, the value to look at, rather than the column.
StudyOutcome job_naming_reused_non_finite(const LoadedStudy& study, StudyRun& run, const Checkpoints& checkpoints) {
  try {
    return study.job(run);
  } catch (const std::invalid_argument& e) {
    const std::string reused = checkpoints.reused_non_finite();
    if (reused.empty()) throw;
    throw StudyResumeError(fmt::format("{}, reused by --resume, and the study refused it ({}); run without --resume",
                                       reused, e.what()));
  }
}

}  // namespace

int run_study_job(const LoadedStudy& study, const StudyRunOptions& opt) {
  // Under MPI ranks (docs/distributed.md) every rank runs the job, its loops dealt to the ranks;
  // rank 0 writes OUT/NAME, the others stage into a private folder removed at the end.
  const bool writer = is_output_rank();
  std::optional<ScratchFolder> scratch;
  if (!writer) scratch.emplace("vrv-study-rank", "this rank's copy of the study");
  StudyStaging staging(writer ? fs::path(opt.out) : scratch->dir(), study.name, opt.resume);
  set_interrupt_cleanup_dir(staging.dir());
  struct ClearCleanup {
    ~ClearCleanup() { set_interrupt_cleanup_dir({}); }
  } clear_cleanup;
  ReferenceAudit audit_counts;  // before the checkpoints: their stores write its snapshots
  Checkpoints checkpoints(staging.dir() / "checkpoints",
                          study.text + (opt.quick ? "\n# --quick" : "\n# full"), staging.resumed());

  const auto start = std::chrono::steady_clock::now();
  StudyOutcome outcome;
  {
    const ThreadLimit limit(opt.threads);
    const PixelSharing sharing;  // every rank meets the job's loops in the same order
    // A checkpointed loop is not dealt (a rank's checkpoints would be its own): none over ranks,
    // where --resume is refused.
    StudyRun run{staging.dir(), opt.quick, !opt.quiet, rank_count() > 1 ? nullptr : &checkpoints, audit_counts};
    audit_counts.start(checkpoints, staging.resumed());  // a resumed run: from the stored counts
    outcome = job_naming_reused_non_finite(study, run, checkpoints);
    const ReferenceAuditCounts audit = audit_counts.counts_over_ranks();
    outcome.checks.push_back(reference_audit_check(audit));
    outcome.parameters["reference_audit"] = {{"truths_computed", audit.rays}, {"missed", audit.missed},
                                             {"largest_estimate", audit.largest_estimate}};
  }
  for (StudyCheck& c : outcome.checks)  // a check must say where its bound comes from
    if (c.kind == CheckKind::unlabelled) {
      c.pass = false;
      c.detail += " [no kind: a check is derived, regression or identity]";
    }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const bool checks_pass = std::all_of(outcome.checks.begin(), outcome.checks.end(),
                                       [](const StudyCheck& c) { return c.pass; });
  const CheckTables t = check_tables(study.name, outcome.checks);
  write_file_atomically(staging.dir() / "checks.csv", t.csv);
  write_file_atomically(staging.dir() / "checks.md", t.md);
  write_file_atomically(staging.dir() / "checks.tex", t.tex);

  std::error_code ec;
  int plots_status = 0;
  std::string plots = "none";
  const PlotScript script = find_plot_script(study_dirs());
  if (fs::exists(staging.dir() / "plots.json", ec)) {
    if (!opt.no_plots && writer) {
      plots_status = draw_plots(staging.dir(), script);
      plots = plots_status == 0 ? "drawn" : fmt::format("failed (exit {})", plots_status);
    } else {
      plots = "not drawn (--no-plots)";
    }
  }
  const bool pass = checks_pass && plots_status == 0;
  write_file_atomically(staging.dir() / "meta.json",
                        meta_json(study, opt, outcome, seconds, pass, plots).dump(2) + "\n");
  fs::remove_all(staging.dir() / "checkpoints", ec);  // the published run is the tables alone
  staging.publish();

  nlohmann::ordered_json j;
  j["study"] = study.name;
  j["out"] = staging.target().string();
  j["pass"] = pass;
  std::cout << j.dump() << '\n';
  if (!checks_pass) {
    std::cerr << fmt::format("vrv study: {}: FAILED: {}\n", study.name, failures(outcome.checks));
    return 1;
  }
  if (plots_status != 0) {
    std::cerr << fmt::format("vrv study: {}: plots: {}, or pass --no-plots\n", study.name,
                             plot_failure(script, plots_status));
    return 1;
  }
  if (!opt.quiet)
    std::cerr << fmt::format("vrv study: {}: {}; {} checks pass in {:.2f} s{}; wrote {}\n", study.name,
                             outcome.summary, outcome.checks.size(), seconds,
                             checkpoints.reused() > 0
                                 ? fmt::format(" (resumed: {} configurations from the interrupted run)",
                                               checkpoints.reused())
                                 : std::string(),
                             staging.target().string());
  return 0;
}

std::string draw_study_plots(const std::filesystem::path& dir) {
  const PlotScript script = find_plot_script(study_dirs());
  const int status = draw_plots(dir, script);
  return status == 0 ? std::string() : plot_failure(script, status);
}

}  // namespace vrv
