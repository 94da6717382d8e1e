#include "studies/engine/study_loader.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <toml++/toml.h>

#include "studies/engine/channel_study.h"
#include "studies/engine/memory_budget.h"
#include "lib/work_estimate.h"
#include "studies/engine/study_work.h"

namespace vrv {
namespace {

std::string naming_channel(const StudyFileError& e, int channel) {
  return fmt::format("{} (studying the scene's {} channel)", e.what(), channel_name(channel));
}

// Whether the red channel's error `e` is its own: green or blue plans, or fails otherwise.  An error
// every channel makes alike (a bad key, projections of an RGB scene) names none.
template <class PlanChannel>
bool channel_dependent(const StudyFileError& e, const PlanChannel& plan_channel) {
  for (int channel = 1; channel < 3; ++channel) {
    try {
      plan_channel(channel);
      return true;
    } catch (const StudyFileError& other) {
      if (std::string_view(other.what()) != e.what()) return true;
    }
  }
  return false;
}

}  // namespace

LoadedStudy load_study_text(std::string text, const std::string& source, const std::string& default_name,
                            const StudyLoadOptions& options) {
  LoadedStudy s;
  s.source = source;
  s.text = std::move(text);
  const toml::table doc = parse_study_toml(s.text, s.source);
  const StudyReader r(s.source);
  s.kind = r.string(r.require(doc, "kind", ""), "kind");
  const StudyParse parse = find_study_kind(s.kind);
  if (!parse)
    r.fail("kind", fmt::format("unknown kind '{}' (known: {})", s.kind, fmt::join(study_kinds(), ", ")));
  s.name = doc.contains("name") ? r.string(*doc.get("name"), "name") : default_name;
  if (s.name.empty() || s.name.find_first_of("/\\") != std::string::npos || s.name == "." ||
      s.name == ".." || s.name.front() == '.')
    r.fail("name", fmt::format("'{}' is not a plain directory name", s.name));
  if (doc.contains("description")) s.description = r.string(*doc.get("description"), "description");
  // Before the driver reads the file: drivers build their grids as they read.
  const double limit = options.memory_limit > 0 ? options.memory_limit : default_memory_limit();
  const StudyMemory memory = estimate_study_memory(doc, find_study_grids(s.kind));
  if (memory.bytes > limit)
    r.fail("(memory)", fmt::format("its grids need {}, more than the limit of {} (raise it with "
                                   "--max-memory GIB)", describe(memory), gibibytes(limit)));
  s.memory_bytes = memory.bytes;
  // What the estimate cannot see (volumes, scene files' grids) is spent from the rest as it is read.
  const double left = std::max(limit - memory.bytes, 1.0);
  const StudyReader reader(s.source, left);
  const auto plan_channel = [doc, source = s.source, name = s.name, parse, left](int channel) {
    StudyReader channel_reader(source, left);
    channel_reader.set_channel(channel);
    return parse(StudyInput{doc, channel_reader, channel_study_name(name, channel)});
  };
  StudyPlan plan;
  try {
    plan = parse(StudyInput{doc, reader, s.name});
  } catch (const StudyFileError& e) {
    if (!reader.saw_rgb_scene() || !channel_dependent(e, plan_channel)) throw;
    throw StudyFileError(naming_channel(e, 0));
  }
  s.memory_bytes += reader.memory_spent();  // --all adds the studies up
  if (reader.saw_rgb_scene())
    plan = per_channel_plan(std::move(plan), [plan_channel](int channel) {
      try {
        return plan_channel(channel);
      } catch (const StudyFileError& e) {  // red passed: a check that holds for red, not for this one
        throw StudyFileError(naming_channel(e, channel));
      }
    });
  s.job = std::move(plan.job);
  s.work = std::move(plan.work);
  return s;
}

LoadedStudy load_study_file(const std::filesystem::path& path, const StudyLoadOptions& options) {
  return load_study_text(read_study_text(path), path.string(), path.stem().string(), options);
}

StudyWork estimate_study_work(const LoadedStudy& study, bool quick) {
  try {
    return study.work ? study.work(quick) : StudyWork{};
  } catch (const std::invalid_argument& e) {  // plan_samples: more than 1e12 samples on a ray
    StudyReader(study.source).fail("(work)", e.what());
  }
}

StudyWork check_study_work(const LoadedStudy& study, bool quick, double limit) {
  StudyWork work = estimate_study_work(study, quick);
  const double evaluations = work.evaluations();
  if (!(evaluations <= limit))  // NaN too: an estimate that cannot be made is not allowed
    StudyReader(study.source).fail("(work)", fmt::format(
        "{}{}, above the work limit of {:.2g}; allow it with --max-work {}", quick ? "--quick: " : "",
        describe(work), limit, work_limit_allowing(evaluations)));
  return work;
}

}  // namespace vrv
