#include "studies/engine/channel_study.h"

#include <array>
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
  std::ifstream in(file);
  const nlohmann::json spec = nlohmann::json::parse(in);
  for (nlohmann::json plot : spec.at("plots")) {
    plot["name"] = channel + "_" + plot.at("name").get<std::string>();
    plot["csv"] = channel + "/" + plot.at("csv").get<std::string>();
    if (plot.contains("title")) plot["title"] = channel + ": " + plot["title"].get<std::string>();
    plots.push_back(std::move(plot));
  }
  fs::remove(file);
}

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
    if (run.checkpoints) run.checkpoints->set_key_prefix(name + ".");
    const StudyOutcome one = plan_channel(c).job(channel_run);
    for (StudyCheck check : one.checks) {
      check.name = fmt::format("{}: {}", name, check.name);
      all.checks.push_back(std::move(check));
    }
    all.parameters["channels"][name] = one.parameters;
    all.summary += fmt::format("{}{}: {}", c ? "; " : "", name, one.summary);
    gather_plots(run.dir, name, plots);
  }
  if (run.checkpoints) run.checkpoints->set_key_prefix("");
  if (!plots.empty()) write_file_atomically(run.dir / "plots.json", nlohmann::json{{"plots", plots}}.dump(1) + "\n");
  return all;
}

}  // namespace

StudyPlan per_channel_plan(StudyPlan red, ChannelPlan plan_channel) {
  StudyPlan plan;
  plan.work = [one = std::move(red.work)](bool quick) {
    StudyWork all;
    if (!one) return all;
    const StudyWork w = one(quick);
    for (const char* name : kChannelNames)
      for (const StudyWork::Part& p : w.parts()) all.add(fmt::format("{}: {}", name, p.what), p.rays, p.per_ray);
    return all;
  };
  plan.job = [plan_channel = std::move(plan_channel)](const StudyRun& run) { return run_channels(plan_channel, run); };
  return plan;
}

}  // namespace vrv
