#include "studies/engine/study_work.h"

#include <algorithm>

#include <fmt/format.h>

namespace vrv {

void StudyWork::add(std::string what, double rays, double per_ray) {
  parts_.push_back({std::move(what), rays, per_ray});
}

double StudyWork::evaluations() const {
  double sum = 0;
  for (const Part& p : parts_) sum += p.evaluations();
  return sum;
}

const StudyWork::Part* StudyWork::largest() const {
  const auto it = std::max_element(parts_.begin(), parts_.end(), [](const Part& a, const Part& b) {
    return a.evaluations() < b.evaluations();
  });
  return it == parts_.end() ? nullptr : &*it;
}

nlohmann::json to_json(const StudyWork& work) {
  nlohmann::json parts = nlohmann::json::array();
  for (const StudyWork::Part& p : work.parts())
    parts.push_back({{"what", p.what}, {"rays", p.rays}, {"per_ray", p.per_ray}, {"evaluations", p.evaluations()}});
  return {{"evaluations", work.evaluations()}, {"parts", parts}};
}

std::string describe(const StudyWork& work) {
  const StudyWork::Part* big = work.largest();
  if (!big) return "no field evaluations";
  return fmt::format("about {:.2g} field evaluations (the largest part: {}, {:.0f} ray{} x {:.2g})",
                     work.evaluations(), big->what, big->rays, big->rays == 1 ? "" : "s", big->per_ray);
}

}  // namespace vrv
