#pragma once
// Which discrete raycast meets an error target at the least cost, decided before rendering:
// per segment rule, the largest step whose estimated image error (lib/discrete_error_estimate.h,
// over the camera's pixels) is within the target, and its cost (samples per ray, and seconds per
// sample measured on this machine); the rules ranked by cost.  `vrv plan` prints it.
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

// The options from the command line's words (metric "max" | "rms", rules comma-separated, a
// strategy name), validated; the one parser of them for `vrv plan` and Python's vrv.plan.
PlanOptions plan_options(double target, std::string_view metric, std::string_view rules, std::string_view strategy,
                         double max_work);

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
