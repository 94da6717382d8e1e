#include "studies/engine/channel_study.h"

#include <array>
#include <exception>
#include <stdexcept>
#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "lib/io/atomic_file.h"
#include "studies/engine/checkpoint.h"

namespace vrv {
namespace {

namespace fs = std::filesystem;

constexpr std::array<const char*, 3> kChannelNames{"red", "green", "blue"};

// A channel's plots.json entries, named and pointed at its folder, appended to `plots`; the
// channel's own file is removed (the study's plots are drawn once, from the top folder).
void gather_plots(const fs::path& top, const std::string& channel, nlohmann::json& plots) {
  const fs::path file = top / channel / "plots.json";
  if (!fs::exists(file)) return;
  try {
    std::ifstream in(file);
    const nlohmann::json spec = nlohmann::json::parse(in);
    for (nlohmann::json plot : spec.at("plots")) {
      plot["name"] = channel + "_" + plot.at("name").get<std::string>();
      plot["csv"] = channel + "/" + plot.at("csv").get<std::string>();
      if (plot.contains("title")) plot["title"] = channel + ": " + plot["title"].get<std::string>();
      plots.push_back(std::move(plot));
    }
  } catch (const nlohmann::json::exception& e) {  // a driver's own file: a bug, named
    throw std::runtime_error(fmt::format("{}: plots: {}", file.string(), e.what()));
  }
  fs::remove(file);
}

// The checkpoints' keys carry the channel while it runs, and nothing after.
class ChannelKeys {
 public:
  ChannelKeys(Checkpoints* checkpoints, std::string_view channel) : checkpoints_(checkpoints) {
    if (checkpoints_) checkpoints_->set_key_prefix(fmt::format("{}.", channel));
  }
  ~ChannelKeys() {
    if (checkpoints_) checkpoints_->set_key_prefix("");
  }
  ChannelKeys(const ChannelKeys&) = delete;
  ChannelKeys& operator=(const ChannelKeys&) = delete;

 private:
  Checkpoints* checkpoints_;
};

}  // namespace

std::string_view channel_name(int channel) { return kChannelNames.at(static_cast<std::size_t>(channel)); }
std::string channel_study_name(std::string_view study, int channel) {
  return fmt::format("{}-{}", study, channel_name(channel));
}

namespace {

StudyOutcome run_channels(const ChannelPlan& plan_channel, const StudyRun& run) {
  StudyOutcome all;
  nlohmann::json plots = nlohmann::json::array();
  for (int c = 0; c < 3; ++c) {
    const std::string name = kChannelNames[c];
    StudyRun channel_run = run;
    channel_run.dir = run.dir / name;
    fs::create_directories(channel_run.dir);
    StudyOutcome one;
    {
      const ChannelKeys keys(run.checkpoints, name);
      one = plan_channel(c).job(channel_run);
    }
    for (StudyCheck check : one.checks) {
      check.name = fmt::format("{}: {}", name, check.name);
      all.checks.push_back(std::move(check));
    }
    all.parameters["channels"][name] = one.parameters;
    all.parameters["channels"][name]["channel"] = c;  // of the RGB scene its "scene" holds
    all.summary += fmt::format("{}{}: {}", c ? "; " : "", name, one.summary);
    gather_plots(run.dir, name, plots);
  }
  if (!plots.empty()) write_file_atomically(run.dir / "plots.json", nlohmann::json{{"plots", plots}}.dump(1) + "\n");
  return all;
}

// The work of the variant (`quick`) for every channel, or what estimating it threw.
struct ChannelWork {
  StudyWork work;
  std::exception_ptr error;
};
ChannelWork channels_work(const StudyWorkEstimate& red, bool quick) {
  ChannelWork out;
  if (!red) return out;
  try {
    const StudyWork one = red(quick);
    for (const char* name : kChannelNames)
      for (const StudyWork::Part& p : one.parts()) out.work.add(fmt::format("{}: {}", name, p.what), p.rays, p.per_ray);
  } catch (...) {
    out.error = std::current_exception();
  }
  return out;
}

}  // namespace

StudyPlan per_channel_plan(StudyPlan red, ChannelPlan plan_channel) {
  std::array<ChannelWork, 2> work{channels_work(red.work, false), channels_work(red.work, true)};
  red = {};  // its grids and volumes go now: a channel's are held only while it runs
  for (int channel = 1; channel < 3; ++channel) plan_channel(channel);
  StudyPlan plan;
  plan.work = [work = std::move(work)](bool quick) {
    const ChannelWork& w = work[quick ? 1 : 0];
    if (w.error) std::rethrow_exception(w.error);
    return w.work;
  };
  plan.job = [plan_channel = std::move(plan_channel)](const StudyRun& run) { return run_channels(plan_channel, run); };
  return plan;
}

}  // namespace vrv
