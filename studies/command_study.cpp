// vrv study: runs a study described by a TOML file (studies/NAME.toml or a path) and writes its
// tables into OUT/NAME/.  The engine is lib/study.h; this is the command line around it.
#include <algorithm>
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
#include <nlohmann/json.hpp>

#include "lib/parallel.h"
#include "lib/study.h"
#include "studies/commands.h"

namespace vrv::cli {
namespace {

// One line naming what failed: the methods off their expected order, or the failing case rows.
std::string failures(const StudyDefinition& study, const StudyResult& result) {
  std::string out;
  auto add = [&](const std::string& item) { out += (out.empty() ? "" : ", ") + item; };
  if (study.kind == "hard_cases") {
    for (const CaseRow& r : result.cases)
      if (!r.pass)
        add(fmt::format("{} / {} (value {:.6g}, error {:.3g}, bound {:.3g})", r.case_name, r.method,
                        r.value, r.error, r.bound));
    return out;
  }
  for (const OrderRow& o : result.orders)
    if (!o.pass)
      add(fmt::format("{} (observed {:.3f}, expected {:g})", segment_rule_name(o.rule), o.observed,
                      o.expected));
  return out + fmt::format(" (tolerance {:g})", study.tolerance);
}


namespace fs = std::filesystem;

struct StudyOptions {
  std::string study;
  bool list = false;
  bool quick = false;
  std::string out = "results";
  int threads = 0;
  bool quiet = false;
};

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

int run_study(const StudyOptions& opt) {
  if (opt.list) {
    if (!opt.study.empty()) throw std::invalid_argument("--list: takes no study name");
    for (const auto& [name, path] : find_studies()) {
      std::string desc;
      try {
        desc = load_study(path).description;
      } catch (const std::exception& e) {
        desc = std::string("(invalid: ") + e.what() + ")";
      }
      std::cout << fmt::format("{}\t{}\t{}\n", name, path.string(), desc);
    }
    return 0;
  }
  if (opt.study.empty()) throw std::invalid_argument("study: give a study NAME or FILE.toml (or --list)");
  if (opt.threads < 0) throw std::invalid_argument(fmt::format("--threads: must not be negative, got {}", opt.threads));
  StudyDefinition study;
  try {
    study = load_study(resolve_study(opt.study));
  } catch (const StudyFileError& e) {
    throw std::invalid_argument(e.what());
  }
  const fs::path dir = fs::path(opt.out) / study.name;
  const auto start = std::chrono::steady_clock::now();
  StudyResult result;
  {
    const ThreadLimit limit(opt.threads);
    result = run_convergence(study, opt.quick, !opt.quiet);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  write_study(dir, study, result, study_parameters(study, opt.quick, opt.threads), seconds);
  nlohmann::ordered_json j;
  j["study"] = study.name;
  j["out"] = dir.string();
  j["pass"] = result.pass;
  std::cout << j.dump() << '\n';
  if (!result.pass) {
    std::cerr << fmt::format("vrv study: {}: FAILED: {}\n", study.name, failures(study, result));
    return 1;
  }
  if (!opt.quiet) {
    const std::string what = study.kind == "hard_cases"
                                 ? fmt::format("{} cases, all pass", result.case_summary.size())
                                 : fmt::format("{} rays, all orders within {:g}", result.rays, study.tolerance);
    std::cerr << fmt::format("vrv study: {}: {} in {:.2f} s; wrote {}\n", study.name, what, seconds,
                             dir.string());
  }
  return 0;
}

}  // namespace

void add_study_command(CLI::App& app) {
  auto opt = std::make_shared<StudyOptions>();
  CLI::App* cmd = app.add_subcommand(
      "study", "Run a study (TOML data: studies/NAME.toml or FILE.toml) and write its tables");
  cmd->footer(
      "Studies are looked up as studies/NAME.toml in ./studies, <vrv's directory>/../studies, "
      "$VRV_STUDY_PATH and the source tree vrv was built from.\n"
      "Writes OUT/NAME/: convergence studies errors.csv, orders.{csv,md,tex}; hard_cases studies "
      "cases.{csv,md,tex}; both meta.json. stdout: one JSON line {\"study\", \"out\", \"pass\"}; "
      "exit 1 when a check fails (a method off its expected order, a failing case).\n"
      "See docs/studies.md.");
  cmd->add_option("study", opt->study, "Study NAME (studies/NAME.toml) or FILE.toml");
  cmd->add_flag("--list", opt->list, "List the studies found");
  cmd->add_flag("--quick", opt->quick, "Fewer rays (the study's quick_count)");
  cmd->add_option("--out", opt->out, "Output directory (results go into OUT/NAME/)")->capture_default_str();
  cmd->add_option("--threads", opt->threads, "Threads (default: all cores); results do not depend on it");
  cmd->add_flag("--quiet", opt->quiet, "No progress bar or summary on stderr");
  cmd->callback([opt] {
    const int rc = run_study(*opt);
    if (rc != 0) std::exit(rc);
  });
}

}  // namespace vrv::cli
