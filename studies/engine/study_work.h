#pragma once
// A study's work, estimated from its parsed file before anything is cast: field evaluations
// (discrete samples and the reference's evaluations, lib/work_estimate.h) summed over the parts
// its driver declares.  `vrv study` refuses a study above its work limit (--max-work) with the
// estimate and its largest part, as it refuses one whose grids do not fit (memory_budget.h):
// a study of many large configurations would otherwise run for hours without a word.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace vrv {

// The default limit: at the 6e6 to 3e7 evaluations a second the shipped studies run at on two
// cores (docs/robustness.md, "Work limits"), 5 to 30 minutes; 16 times the largest shipped study
// (visibility, 6.1e8).  Longer studies say so with --max-work.
inline constexpr double kDefaultStudyWorkLimit = 1e10;

class StudyWork {
 public:
  struct Part {
    std::string what;  // e.g. "images at rate 8 (trapezoid)"
    double rays = 0;
    double per_ray = 0;  // evaluations per ray (on the longest ray: an upper estimate)
    double evaluations() const { return rays * per_ray; }
  };

  // `rays` rays of about `per_ray` field evaluations each.
  void add(std::string what, double rays, double per_ray);
  double evaluations() const;
  const std::vector<Part>& parts() const { return parts_; }
  const Part* largest() const;  // null when nothing was added

 private:
  std::vector<Part> parts_;
};

// {"evaluations", "parts": [{"what", "rays", "per_ray", "evaluations"}, ...]} (vrv study --estimate,
// meta.json).
nlohmann::json to_json(const StudyWork& work);

// "about 3.2e+11 field evaluations (the largest part: images at rate 8, 65536 rays x 4.9e+06)".
std::string describe(const StudyWork& work);

}  // namespace vrv
