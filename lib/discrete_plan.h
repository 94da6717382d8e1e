#pragma once
// Which discrete raycast meets an error target at the least cost, decided before rendering:
// per segment rule, the largest step whose estimated image error (lib/discrete_error_estimate.h,
// over the camera's pixels) is within the target, and its cost (samples per ray, and seconds per
// sample measured on this machine); the rules ranked by cost.  `vrv plan` prints it.
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "lib/camera.h"
#include "lib/discrete_raycast.h"
#include "lib/metrics.h"
#include "lib/scene.h"

namespace vrv {

struct PlanOptions {
  double target = 1e-3;          // the error the image may have (> 0)
  Metric metric = Metric::max;   // over the pixels: max or rms
  std::vector<SegmentRule> rules{SegmentRule::riemann, SegmentRule::alpha, SegmentRule::trapezoid,
                                 SegmentRule::exact_linear};
  Strategy strategy = Strategy::step;  // a step-based placement (step, vtk, inviwo)
  // Field evaluations one image estimate may take: a step needing more is not tried (the rule is
  // then reported as not met at the smallest step tried).
  double max_work = 1e9;
};

// Throws std::invalid_argument naming the option (--target, --metric, --rules, --strategy, --max-work).
void validate(const PlanOptions& options);

// The placements a plan takes, "step, vtk, inviwo" (kWholeStepStrategies).
std::string plan_strategy_list();
// Rules as --rules takes them: "riemann,alpha".
std::string comma_separated(const std::vector<SegmentRule>& rules);

// What `vrv plan`'s options and vrv.plan's keywords set alike, as the user types them (metric
// "max" | "rms", rules comma-separated, a strategy name); the defaults are PlanOptions' own, and
// the command line and the Python module bind these fields.  The target has none: it is required.
struct PlanSettings {
  double target = 0;
  std::string metric{metric_name(PlanOptions{}.metric)};
  std::string rules = comma_separated(PlanOptions{}.rules);
  std::string strategy{strategy_name(PlanOptions{}.strategy)};
  double max_work = PlanOptions{}.max_work;
};
// The camera's sides a plan estimates over unless given (the scene's camera at this size).
inline constexpr int kPlanImageSide = 32;

// The options from the settings, validated; the one parser of them for `vrv plan` and vrv.plan.
PlanOptions plan_options(const PlanSettings& settings);

struct PlannedRule {
  DiscreteConfig config;         // the rule at the step chosen
  double estimated_error = 0;    // the metric of the estimates at that step
  double samples_per_ray = 0;    // mean over the camera's rays
  double seconds_per_sample = 0; // measured: the fastest of repeated renders of the camera at that step
  double seconds = 0;            // for the camera: samples x seconds per sample
  int estimates = 0;             // image estimates made to find the step
  bool met = false;              // a step within the target was found (false: the smallest tried)
};

struct DiscretePlan {
  std::vector<PlannedRule> ranked;  // cheapest first; those not met last
  long evaluations = 0;             // field evaluations the estimates took
};

// The scene must be grey.  Throws std::invalid_argument for an invalid option or an RGB scene.
DiscretePlan plan_discrete(const Scene& scene, const Camera& camera, const PlanOptions& options);

// {"ranked": [{"rule", "strategy", "step", "estimated_error", "met", "samples_per_ray",
// "seconds_per_sample", "seconds", "estimates"}, ...], "evaluations"}: what `vrv plan --json`
// prints and vrv.plan returns.
nlohmann::ordered_json to_json(const DiscretePlan& plan);

}  // namespace vrv
