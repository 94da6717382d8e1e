#pragma once
// Running one study, the same way for every kind: the driver's job writes into the staging folder
// (staging.h), with checkpoints for --resume (checkpoint.h); then checks.{csv,md,tex}, the plots
// (studies/plot_study.py, a child process that an interruption ends) and meta.json, which says
// pass only when every check passed and the plots were drawn; then the folder is published in one
// step.  SIGINT/SIGTERM stop it promptly with the previous results intact (interrupt.h).
#include <filesystem>
#include <string>

#include "studies/engine/study_loader.h"

namespace vrv {

struct StudyRunOptions {
  std::filesystem::path out = "results";  // results go to OUT/NAME/
  bool quick = false;                     // the --quick variant
  bool progress = false;                  // a progress bar on stderr
  bool quiet = false;                     // no summary line on stderr
  bool plots = true;                      // run the plot script when the driver wrote plots.json
  bool resume = false;                    // continue an interrupted run's checkpoints
  int threads = 0;                        // recorded in meta.json (the caller limits threads)
  std::string python = "python3";         // the plot script's interpreter
  std::filesystem::path plot_script;      // studies/plot_study.py
};

// Runs the study and publishes OUT/NAME; prints {"study", "out", "pass"} on stdout.  Returns 0
// when every check passes and the plots were drawn, else 1 (after one line on stderr).  Throws
// std::runtime_error (one line) when an output cannot be written, StudyResumeError for a --resume
// that does not match.
int run_loaded_study(const LoadedStudy& study, const StudyRunOptions& options);

}  // namespace vrv
