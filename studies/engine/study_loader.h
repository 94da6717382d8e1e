#pragma once
// A study file, read and checked before anything runs: the common keys (kind, name, description),
// the memory budget (memory_budget.h), then its kind's driver parses the rest into a job.  Every
// problem is a StudyFileError, one line naming the file and key (exit 2).
#include <filesystem>
#include <string>

#include "lib/study_file.h"
#include "studies/engine/study_driver.h"

namespace vrv {

struct StudyLoadOptions {
  double memory_limit = 0;  // bytes the study's grids may take; 0: default_memory_limit()
};

struct LoadedStudy {
  std::string name, kind, description, text, source;
  StudyJob job;
  StudyWorkEstimate work;   // its field evaluations, full or --quick (study_work.h)
  double memory_bytes = 0;  // its grids: the file's estimate (memory_budget.h) and what was read beyond it
};

// `source` names the file in messages and anchors relative paths (scene = "FILE"); `default_name`
// is the study's name when the file has no `name` key (its stem).
LoadedStudy load_study_text(std::string text, const std::string& source, const std::string& default_name,
                            const StudyLoadOptions& options = {});
LoadedStudy load_study_file(const std::filesystem::path& path, const StudyLoadOptions& options = {});

// The study's work for the variant (`quick`); a configuration the estimate cannot plan (more than
// 1e12 samples on a ray) is a StudyFileError "FILE: (work): ...".
StudyWork estimate_study_work(const LoadedStudy& study, bool quick);
// ... and a StudyFileError ("FILE: (work): ...", exit 2) with the estimate, its largest part and
// the --max-work that would allow it when above `limit`.
StudyWork check_study_work(const LoadedStudy& study, bool quick, double limit);

}  // namespace vrv
