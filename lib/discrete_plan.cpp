#include "lib/discrete_plan.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "lib/discrete_error_bound.h"
#include "lib/discrete_error_estimate.h"
#include "lib/option_error.h"
#include "lib/util/parallel.h"
#include "lib/vrv.h"
#include "lib/work_estimate.h"

namespace vrv {

std::string plan_strategy_list() { return strategy_list(kWholeStepStrategies); }

std::string comma_separated(const std::vector<SegmentRule>& rules) {
  std::string s;
  for (const SegmentRule r : rules) s.append(s.empty() ? "" : ",").append(segment_rule_name(r));
  return s;
}

void validate(const PlanOptions& o) {
  if (!(o.target > 0) || !std::isfinite(o.target))
    throw OptionError(Option::target, fmt::format("must be a positive finite error, got {}", o.target));
  if (o.metric != Metric::max && o.metric != Metric::rms)
    throw OptionError(Option::metric, fmt::format("max or rms, got {}", metric_name(o.metric)));
  if (o.rules.empty()) throw OptionError(Option::rules, "at least one rule");
  if (std::ranges::find(kWholeStepStrategies, o.strategy) == std::end(kWholeStepStrategies))
    throw OptionError(Option::strategy,
                      fmt::format("a step-based placement ({}), got {}", plan_strategy_list(), strategy_name(o.strategy)));
  if (!(o.max_work > 0)) throw OptionError(Option::max_work, fmt::format("must be positive, got {}", o.max_work));
}

PlanOptions plan_options(const PlanSettings& settings) {
  const std::string_view metric = settings.metric, rules = settings.rules, strategy = settings.strategy;
  PlanOptions p;
  p.target = settings.target;
  p.max_work = settings.max_work;
  const auto m = parse_metric(metric);
  if (!m || (*m != Metric::max && *m != Metric::rms))
    throw OptionError(Option::metric, fmt::format("unknown value '{}' (max or rms)", metric));
  p.metric = *m;
  p.rules.clear();
  for (std::size_t start = 0; start <= rules.size();) {
    const std::size_t comma = std::min(rules.find(',', start), rules.size());
    const std::string_view name = rules.substr(start, comma - start);
    const auto rule = parse_segment_rule(name);
    if (!rule)
      throw OptionError(Option::rules,
                        fmt::format("unknown rule '{}' ({})", name, segment_rule_list()));
    // A rule named twice was planned twice (two identical rows).
    if (std::find(p.rules.begin(), p.rules.end(), *rule) != p.rules.end())
      throw OptionError(Option::rules, fmt::format("'{}' listed twice", name));
    p.rules.push_back(*rule);
    start = comma + 1;
  }
  const auto s = parse_strategy(strategy);
  if (!s) throw OptionError(Option::strategy, fmt::format("unknown value '{}' ({})", strategy, plan_strategy_list()));
  p.strategy = *s;
  validate(p);
  return p;
}

namespace {

struct ImageEstimate {
  double step = 0, error = 0, samples_per_ray = 0;
};

ImageEstimate estimate_image(const Scene& scene, const std::vector<Ray>& rays, const DiscreteConfig& config,
                             Metric metric, long& evaluations) {
  std::vector<double> errors(rays.size());
  std::vector<long> work(rays.size()), samples(rays.size());
  parallel_for_index(static_cast<long>(rays.size()), [&](long i) {
    const auto k = static_cast<std::size_t>(i);
    const DiscreteErrorEstimate e = estimate_discrete_error(scene, rays[k], config);
    errors[k] = e.error;
    work[k] = e.evaluations;
    samples[k] = static_cast<long>(discrete_samples(config, scene, rays[k]));
  });
  ErrorSums sums;
  double total = 0;
  for (std::size_t k = 0; k < rays.size(); ++k) {
    sums.add(errors[k]);
    evaluations += work[k];
    total += static_cast<double>(samples[k]);
  }
  return {config.sampling.step, metric_value(sums.stats(), metric), total / static_cast<double>(rays.size())};
}

// Seconds per sample of the rule at this step: the fastest of repeated renders of the camera (at
// least kTimedRenders, and more until kTimedSeconds have passed, at most kMostRenders): a small
// camera renders in a fraction of a millisecond, where one render's time is mostly noise.
double seconds_per_sample(const Scene& scene, const Camera& camera, const DiscreteConfig& config) {
  constexpr int kTimedRenders = 3, kMostRenders = 100;
  constexpr double kTimedSeconds = 0.05;
  using Clock = std::chrono::steady_clock;
  double best = INFINITY, total = 0;
  long work = 0;
  for (int i = 0; i < kMostRenders && (i < kTimedRenders || total < kTimedSeconds); ++i) {
    const auto start = Clock::now();
    work = render_discrete_image(scene, camera, config).work;
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    best = std::min(best, seconds);
    total += seconds;
  }
  return work > 0 ? best / static_cast<double>(work) : 0.0;
}

// Field evaluations of an image estimate at this step, at most: every ray as long as the box's
// diagonal, each segment's proxy and sample.
double estimate_work(std::size_t rays, double longest, double step) {
  return static_cast<double>(rays) * (longest / step + 2) * (1 + kErrorBoundEvaluationsPerSegment);
}

// A target so far below the estimates that, at the order the last two show, the step meeting it
// would take this many times --max-work: the ladder stops instead of walking down to the limit
// (an unreachable --target 1e-300 took 77 s).  The factor leaves room for a pre-asymptotic
// order that rises as the step falls.
constexpr double kHopelessWork = 100;

// The order at which the estimate falls from the coarser step to the finer, or NaN.
double observed_order(const ImageEstimate& coarse, const ImageEstimate& fine) {
  if (!(fine.error > 0 && coarse.error > 0)) return NAN;
  return std::log(coarse.error / fine.error) / std::log(coarse.step / fine.step);
}

// True when the last three ladder estimates fall at one settled order p (at least 1/2, the two
// steps' orders within a quarter of each other: coarse steps are pre-asymptotic, and an order
// read there predicted steps far too fine) and the step (aim/error)^(1/p) that order predicts
// for the target is `too_costly`.
template <class TooCostly>
bool out_of_reach(const ImageEstimate& a, const ImageEstimate& b, const ImageEstimate& c, double aim,
                  TooCostly&& too_costly) {
  const double p1 = observed_order(a, b), p2 = observed_order(b, c);
  if (!(p1 >= 0.5 && p2 >= 0.5 && std::abs(p1 - p2) <= 0.25 * p2)) return false;
  return too_costly(c.step * std::pow(aim / c.error, 1 / p2));
}

// The largest step whose estimate meets the target, as a brute-force search would find it on a
// ladder of steps (errors are not monotone in the step where samples meet breakpoints): down from
// half the box's diagonal by factors of kLadder until one meets it, then bisected (in log h)
// against the step above it.
PlannedRule plan_rule(const Scene& scene, const std::vector<Ray>& rays, SegmentRule rule, const PlanOptions& o,
                      long& evaluations) {
  constexpr double kLadder = 1.25;
  constexpr int kBisections = 4;
  // The estimate misses by a few percent where the steps resolve the field and by more at a few
  // samples per ray (3% at 12 per ray, tests/lib/discrete_error_estimate_test.cpp): a step is taken
  // where its estimate is within this share of the target.
  constexpr double kMargin = 0.9;
  const double aim = kMargin * o.target;
  PlannedRule out;
  out.config.rule = rule;
  out.config.sampling.strategy = o.strategy;
  out.config.sampling.dims = scene.dims;
  const auto at = [&](double step) {
    DiscreteConfig c = out.config;
    c.sampling.step = step;
    ++out.estimates;
    return estimate_image(scene, rays, c, o.metric, evaluations);
  };
  const double longest = (scene.box.max - scene.box.min).norm();
  std::optional<ImageEstimate> met, last, before_last;
  for (double step = longest / 2; estimate_work(rays.size(), longest, step) <= o.max_work; step /= kLadder) {
    const ImageEstimate e = at(step);
    if (e.error <= aim) {
      met = e;
      break;
    }
    const bool hopeless = before_last && out_of_reach(*before_last, *last, e, aim, [&](double h) {
      return estimate_work(rays.size(), longest, h) > kHopelessWork * o.max_work;
    });
    before_last = last;
    last = e;
    if (hopeless) break;
  }
  if (met && last) {
    double above = last->step;
    for (int i = 0; i < kBisections; ++i) {
      const ImageEstimate e = at(std::sqrt(met->step * above));
      (e.error <= aim ? met : last) = e;
      above = last->step;
    }
  }
  if (!met && !last)
    throw OptionError(Option::max_work,
                      fmt::format("one estimate of this camera takes about {:.3g} field evaluations, above {:.3g}; "
                                  "make the camera smaller or allow it with {{0}}",
                                  estimate_work(rays.size(), longest, longest / 2), o.max_work),
                      {Option::max_work});
  const ImageEstimate chosen = met ? *met : *last;
  out.met = met.has_value();
  out.config.sampling.step = chosen.step;
  out.estimated_error = chosen.error;
  out.samples_per_ray = chosen.samples_per_ray;
  return out;
}

}  // namespace

DiscretePlan plan_discrete(const Scene& scene, const Camera& camera, const PlanOptions& options) {
  validate(options);
  require_grey(scene, "the scene", "vrv plan");
  // Everything asked is checked before any work (every rule is estimated on a scene that is).
  DiscreteConfig probe;
  probe.sampling.strategy = options.strategy;
  if (const std::string why = why_no_error_bound(scene, probe); !why.empty())
    throw std::invalid_argument(fmt::format("the scene: no estimate is made for {} (docs/error-bounds.md)", why));
  DiscretePlan plan;
  const std::vector<Ray> rays = camera_rays(camera);
  const Vec3 extent = scene.box.max - scene.box.min;
  // A voxel of the scene's nominal grid: a cheap step for the warm-up render.
  const double voxel = std::min({extent.x() / scene.dims[0], extent.y() / scene.dims[1], extent.z() / scene.dims[2]});
  // The first render of a process also starts TBB's threads: not a cost of the first rule.
  DiscreteConfig warm;
  warm.sampling.strategy = Strategy::step;
  warm.sampling.step = voxel;
  render_discrete_image(scene, camera, warm);
  for (SegmentRule rule : options.rules) {
    PlannedRule r = plan_rule(scene, rays, rule, options, plan.evaluations);
    r.seconds_per_sample = seconds_per_sample(scene, camera, r.config);
    r.seconds = r.samples_per_ray * static_cast<double>(rays.size()) * r.seconds_per_sample;
    plan.ranked.push_back(r);
  }
  std::stable_sort(plan.ranked.begin(), plan.ranked.end(), [](const PlannedRule& a, const PlannedRule& b) {
    return a.met != b.met ? a.met : a.seconds < b.seconds;
  });
  return plan;
}

nlohmann::ordered_json to_json(const DiscretePlan& plan) {
  nlohmann::ordered_json j;
  j["ranked"] = nlohmann::ordered_json::array();
  for (const PlannedRule& r : plan.ranked)
    j["ranked"].push_back({{"rule", segment_rule_name(r.config.rule)},
                           {"strategy", strategy_name(r.config.sampling.strategy)},
                           {"step", r.config.sampling.step},
                           {"estimated_error", r.estimated_error},
                           {"met", r.met},
                           {"samples_per_ray", r.samples_per_ray},
                           {"seconds_per_sample", r.seconds_per_sample},
                           {"seconds", r.seconds},
                           {"estimates", r.estimates}});
  j["evaluations"] = plan.evaluations;
  return j;
}

}  // namespace vrv
