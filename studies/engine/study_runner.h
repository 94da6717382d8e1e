#pragma once
// The study engine, the same for every kind: finds study files (studies/NAME/NAME.toml), reads
// the keys every file has (kind, name, description) and hands the rest to the kind's driver
// (study_driver.h), runs the job in OUT/NAME/, writes checks.{csv,md,tex} and meta.json (run
// metadata, the full study file, the checks) and draws the plots (plot_study.py).  It knows no
// study kind.  The command line around it is studies/cli/study.cpp.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "studies/engine/study_driver.h"
#include "studies/engine/study_loader.h"  // LoadedStudy, load_study_file

namespace vrv {

// Where studies are looked for, in order: ./studies, <executable dir>/../studies,
// $VRV_STUDY_PATH, and the source tree this file was compiled from.
std::vector<std::filesystem::path> study_dirs();

// Every study found: a folder NAME/ holding NAME.toml in a search directory; the first one wins
// per name; in name order within a directory.
std::vector<std::pair<std::string, std::filesystem::path>> find_studies();

// Runs plot_study.py on `dir` (which has plots.json), as a study's run does; "" when the plot was
// drawn, else why not (one line, plot_script.h).  `vrv verify --plots` draws its plot this way.
std::string draw_study_plots(const std::filesystem::path& dir);

// A NAME (found as above) or a path to a .toml file; throws std::invalid_argument for an
// unknown name.
std::filesystem::path resolve_study(const std::string& arg);

struct StudyRunOptions {
  bool quick = false;          // the study's --quick variant
  std::string out = "results";  // results go into OUT/NAME/ (staged in OUT/.NAME.partial/)
  int threads = 0;             // 0: all cores; no number depends on it
  bool quiet = false;          // no progress bar or summary on stderr
  bool no_plots = false;       // do not run plot_study.py
  bool resume = false;         // continue an interrupted run from its checkpoints
};

// Runs one study into its staging folder (staging.h) with checkpoints (checkpoint.h), writes
// checks.{csv,md,tex}, draws the plots (a child process that an interruption ends), writes
// meta.json (pass only when every check passed and the plots were drawn) and publishes the folder
// in one step.  0 when every check passes and the plots were drawn, 1 otherwise (one line on
// stderr naming the failed checks or the plot script).  Throws std::runtime_error (one line)
// when an output cannot be written, StudyResumeError for a --resume that does not match.
int run_study_job(const LoadedStudy& study, const StudyRunOptions& opt);

}  // namespace vrv
