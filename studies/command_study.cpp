// vrv study: runs a study described by a TOML file (studies/NAME.toml or a path) and writes its
// tables into OUT/NAME/.  The engine is lib/study.h; this is the command line around it.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iostream>
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
#include "lib/atomic_file.h"
#include "lib/run_metadata.h"
#include "lib/study_file.h"
#include "studies/study_driver.h"
#include "studies/commands.h"

namespace vrv::cli {
namespace {

// One line naming the failed checks.
std::string failures(const std::vector<StudyCheck>& checks) {
  std::string out;
  for (const StudyCheck& c : checks)
    if (!c.pass)
      out += fmt::format("{}{} (value {:.4g}, bound {:.4g})", out.empty() ? "" : ", ", c.name,
                         c.value, c.bound);
  return out;
}

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
};

// A study file, read and checked: its kind's driver has parsed it into a job.
struct LoadedStudy {
  std::string name, kind, description, text, source;
  StudyJob job;
};

LoadedStudy load(const fs::path& path) {
  LoadedStudy s;
  s.source = path.string();
  s.text = read_study_text(path);
  const toml::table doc = parse_study_toml(s.text, s.source);
  const StudyReader r(s.source);
  s.kind = r.string(r.require(doc, "kind", ""), "kind");
  const StudyParse parse = find_study_kind(s.kind);
  if (!parse)
    r.fail("kind", fmt::format("unknown kind '{}' (known: {})", s.kind, fmt::join(study_kinds(), ", ")));
  s.name = doc.contains("name") ? r.string(*doc.get("name"), "name") : path.stem().string();
  if (s.name.empty() || s.name.find_first_of("/\\") != std::string::npos || s.name == "." ||
      s.name == "..")
    r.fail("name", fmt::format("'{}' is not a plain directory name", s.name));
  if (doc.contains("description")) s.description = r.string(*doc.get("description"), "description");
  s.job = parse(StudyInput{doc, r, s.name});
  return s;
}

// The plot script (studies/plot_study.py) next to the study files, and a Python that has
// matplotlib: $VRV_PYTHON, else Debian's /usr/bin/python3 (python3-matplotlib), else python3.
fs::path plot_script();
std::string python();

// Runs the plot script on `dir` (which has plots.json); its messages go to stderr.  Returns its
// exit status (127 when it could not be started).
int draw_plots(const fs::path& dir) {
  const std::string py = python();
  const std::string script = plot_script().string();
  const std::string where = dir.string();
  const pid_t pid = fork();
  if (pid < 0) return 127;
  if (pid == 0) {
    const char* argv[] = {py.c_str(), script.c_str(), where.c_str(), nullptr};
    execvp(argv[0], const_cast<char* const*>(argv));
    _exit(127);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return 127;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

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

int run_study(const StudyOptions& opt) {
  if (opt.list) {
    if (!opt.study.empty()) throw std::invalid_argument("--list: takes no study name");
    for (const auto& [name, path] : find_studies()) {
      std::string desc;
      try {
        desc = load(path).description;
      } catch (const std::exception& e) {
        desc = std::string("(invalid: ") + e.what() + ")";
      }
      std::cout << fmt::format("{}\t{}\t{}\n", name, path.string(), desc);
    }
    return 0;
  }
  if (opt.threads < 0) throw std::invalid_argument(fmt::format("--threads: must not be negative, got {}", opt.threads));
  if (opt.all) {
    if (!opt.study.empty()) throw std::invalid_argument("--all: takes no study name");
    // Every study file is checked before any runs, so a bad file costs no time.
    std::vector<LoadedStudy> studies;
    for (const auto& [name, path] : find_studies()) {
      try {
        studies.push_back(load(path));
      } catch (const StudyFileError& e) {
        throw std::invalid_argument(e.what());
      }
    }
    int rc = 0;
    for (const LoadedStudy& s : studies) rc = std::max(rc, run_one(s, opt));
    return rc;
  }
  if (opt.study.empty())
    throw std::invalid_argument("study: give a study NAME or FILE.toml (or --all, --list)");
  LoadedStudy study;
  try {
    study = load(resolve_study(opt.study));
  } catch (const StudyFileError& e) {
    throw std::invalid_argument(e.what());
  }
  return run_one(study, opt);
}

// Runs one study and writes its files; 0 when every check passes and the plots were drawn.
int run_one(const LoadedStudy& study, const StudyOptions& opt) {
  const fs::path dir = fs::path(opt.out) / study.name;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir))
    throw std::runtime_error(fmt::format("{}: cannot create the directory{}", dir.string(),
                                         ec ? ": " + ec.message() : std::string()));
  const auto start = std::chrono::steady_clock::now();
  StudyOutcome outcome;
  {
    const ThreadLimit limit(opt.threads);
    outcome = study.job(StudyRun{dir, opt.quick, !opt.quiet});
  }
  for (StudyCheck& c : outcome.checks)  // a check must say where its bound comes from
    if (c.kind == CheckKind::unlabelled) {
      c.pass = false;
      c.detail += " [no kind: a check is derived, regression or identity]";
    }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const bool pass = std::all_of(outcome.checks.begin(), outcome.checks.end(),
                                [](const StudyCheck& c) { return c.pass; });
  const CheckTables t = check_tables(study.name, outcome.checks);
  write_file_atomically(dir / "checks.csv", t.csv);
  write_file_atomically(dir / "checks.md", t.md);
  write_file_atomically(dir / "checks.tex", t.tex);
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
  meta["summary"] = outcome.summary;
  nlohmann::json checks = nlohmann::json::array();
  for (const StudyCheck& c : outcome.checks)
    checks.push_back({{"name", c.name},
                      {"value", std::isfinite(c.value) ? nlohmann::json(c.value) : nlohmann::json()},
                      {"bound", std::isfinite(c.bound) ? nlohmann::json(c.bound) : nlohmann::json()},
                      {"pass", c.pass},
                      {"kind", check_kind_name(c.kind)},
                      {"detail", c.detail}});
  meta["checks"] = checks;
  write_file_atomically(dir / "meta.json", meta.dump(2) + "\n");

  int plots_status = 0;
  if (!opt.no_plots && fs::exists(dir / "plots.json")) plots_status = draw_plots(dir);
  nlohmann::ordered_json j;
  j["study"] = study.name;
  j["out"] = dir.string();
  j["pass"] = pass;
  std::cout << j.dump() << '\n';
  if (!pass) {
    std::cerr << fmt::format("vrv study: {}: FAILED: {}\n", study.name, failures(outcome.checks));
    return 1;
  }
  if (plots_status != 0) {
    std::cerr << fmt::format(
        "vrv study: {}: plots: {} {} exited with {} (matplotlib: Debian's python3-matplotlib; "
        "set VRV_PYTHON, or pass --no-plots)\n",
        study.name, python(), plot_script().string(), plots_status);
    return 1;
  }
  if (!opt.quiet)
    std::cerr << fmt::format("vrv study: {}: {}; {} checks pass in {:.2f} s; wrote {}\n", study.name,
                             outcome.summary, outcome.checks.size(), seconds, dir.string());
  return 0;
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
      "exit 1 when a check fails or the plots cannot be drawn, 2 for a bad study file.\n"
      "See docs/studies.md.");
  cmd->add_option("study", opt->study, "Study NAME (studies/NAME.toml) or FILE.toml");
  cmd->add_flag("--list", opt->list, "List the studies found");
  cmd->add_flag("--all", opt->all, "Run every study found, in name order (results/ is --all --out results)");
  cmd->add_flag("--quick", opt->quick, "Fewer rays (the study's quick_count)");
  cmd->add_option("--out", opt->out, "Output directory (results go into OUT/NAME/)")->capture_default_str();
  cmd->add_option("--threads", opt->threads, "Threads (default: all cores); results do not depend on it");
  cmd->add_flag("--quiet", opt->quiet, "No progress bar or summary on stderr");
  cmd->add_flag("--no-plots", opt->no_plots, "Do not run the plot script (studies/plot_study.py)");
  cmd->callback([opt] {
    const int rc = run_study(*opt);
    if (rc != 0) std::exit(rc);
  });
}

}  // namespace vrv::cli
