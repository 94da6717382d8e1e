// vrv plan: which discrete raycast meets an error target on a scene's camera at the least cost,
// predicted before anything is rendered (lib/discrete_plan.h); --check renders the chosen one and
// its reference and compares the measured error with the prediction.
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "lib/discrete_plan.h"
#include "lib/metrics.h"
#include "lib/shared_options.h"
#include "lib/vrv.h"
#include "studies/cli/cli_support.h"
#include "studies/cli/memory_limit.h"
#include "studies/cli/discrete_flags.h"
#include "studies/cli/commands.h"

namespace vrv::cli {
namespace {

struct PlanCommandOptions {
  std::string scene;
  std::optional<double> max_memory_gib;  // --max-memory: the scene's volume
  PlanSettings settings;
  std::optional<int> width = kPlanImageSide, height = kPlanImageSide;
  bool check = false;
  double tol = kImagesReferenceTol;
  bool json = false;
};

struct Check {
  double measured = 0;
  bool met = false;
};

// The chosen configuration's image against the reference, over the same pixels.
Check check_plan(const Scene& scene, const Camera& camera, const PlannedRule& chosen, const PlanOptions& p, double tol) {
  const ValueImage reference = render_reference_image(scene, camera, {tol});
  const ValueImage discrete = render_discrete_image(scene, camera, chosen.config);
  ErrorSums sums;
  for (std::size_t i = 0; i < reference.pixels.size(); ++i) sums.add(discrete.pixels[i] - reference.pixels[i]);
  const double measured = metric_value(sums.stats(), p.metric);
  return {measured, measured <= p.target};
}

void run_plan(const PlanCommandOptions& o) {
  const PlanOptions p = plan_options(o.settings);
  check_tolerance(o.tol);
  const Scene scene = load_scene_or_default(o.scene, memory_limit_bytes(o.max_memory_gib));
  require_unshaded(scene, o.scene.empty() ? "the default scene" : o.scene, "vrv plan");
  require_grey(scene, o.scene.empty() ? "the default scene" : o.scene, "vrv plan");
  require_emission_absorption(o.scene, "vrv plan");
  const Camera camera = scene_camera(scene, o.width, o.height);
  const DiscretePlan plan = plan_discrete(scene, camera, p);
  const PlannedRule& chosen = plan.ranked.front();
  std::optional<Check> check;
  if (o.check && chosen.met) check = check_plan(scene, camera, chosen, p, o.tol);
  if (o.json) {
    nlohmann::ordered_json j;
    j["target"] = p.target;
    j["metric"] = metric_name(p.metric);
    j["pixels"] = camera.width * camera.height;
    j.update(to_json(plan));
    if (check) j["check"] = {{"measured_error", check->measured}, {"met", check->met}};
    std::cout << j.dump() << '\n';
  } else {
    fmt::print("target: {} error {:g} over {}x{} pixels of the scene camera\n", metric_name(p.metric), p.target,
               camera.width, camera.height);
    fmt::print("{:<13} {:>11} {:>15} {:>12} {:>11} {:>11}  {}\n", "rule", "step", "estimated", "samples/ray",
               "s/sample", "seconds", "met");
    for (const PlannedRule& r : plan.ranked)
      fmt::print("{:<13} {:>11.4g} {:>15.3g} {:>12.1f} {:>11.3g} {:>11.3g}  {}\n", segment_rule_name(r.config.rule),
                 r.config.sampling.step, r.estimated_error, r.samples_per_ray, r.seconds_per_sample, r.seconds,
                 r.met ? "yes" : "no");
    if (chosen.met)
      fmt::print("chosen: --method {} --strategy {} --step {:.6g}\n", segment_rule_name(chosen.config.rule),
                 strategy_name(chosen.config.sampling.strategy), chosen.config.sampling.step);
    if (check)
      fmt::print("check: measured {} error {:.3g} (estimated {:.3g}): {}\n", metric_name(p.metric), check->measured,
                 chosen.estimated_error, check->met ? "within the target" : "ABOVE the target");
  }
  std::cout << std::flush;
  if (!chosen.met)
    throw CommandFailed(kExitCheckFailed, fmt::format("vrv plan: no rule meets {} error {:g} within --max-work {:g}",
                                                      metric_name(p.metric), p.target, p.max_work));
  if (check && !check->met)
    throw CommandFailed(kExitCheckFailed, fmt::format("vrv plan: --check: the measured {} error {:.3g} is above the "
                                                      "target {:g}", metric_name(p.metric), check->measured, p.target));
}

}  // namespace

void add_plan_command(CLI::App& app) {
  auto opt = std::make_shared<PlanCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "plan", "Which discrete raycast meets an error target at the least cost, predicted before rendering");
  cmd->footer(
      "Per rule, the largest step whose estimated image error (docs/error-bounds.md, \"Estimates\") is within "
      "--target over the camera's pixels, its samples per ray and measured seconds per sample; ranked cheapest "
      "first.\nExit: 0; 1 no rule meets the target, or --check measured an error above it; 2 bad input.");
  cmd->add_option("--scene", opt->scene, "Scene file (TOML); the embedded default when omitted");
  add_volume_memory_option(*cmd, opt->max_memory_gib);
  cmd->add_option("--target", opt->settings.target, "The error the image may have")->required();
  cmd->add_option("--metric", opt->settings.metric, "Over the pixels: max or rms")->capture_default_str();
  cmd->add_option("--rules", opt->settings.rules, "Rules to plan, comma-separated")->capture_default_str();
  cmd->add_option("--strategy", opt->settings.strategy, "A step-based placement: " + plan_strategy_list())->capture_default_str();
  add_shared_option(*cmd, Option::width, opt->width);
  add_shared_option(*cmd, Option::height, opt->height);
  cmd->add_option("--max-work", opt->settings.max_work, "Field evaluations one image estimate may take")->capture_default_str();
  cmd->add_flag("--check", opt->check, "Render the chosen configuration and its reference; compare the errors");
  // Only --check renders a reference: without it --tol would be accepted and ignored.
  add_shared_option(*cmd, Option::tol, opt->tol, "(--check's reference image)")->needs(cmd->get_option("--check"));
  cmd->add_flag("--json", opt->json, "One JSON line");
  cmd->callback([opt] { run_plan(*opt); });
}

}  // namespace vrv::cli
