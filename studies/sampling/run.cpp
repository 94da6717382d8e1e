// Running the sampling study; see run.h.  Tables and images are written by
// files.cpp.
#include "studies/sampling/run.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "lib/order_estimate.h"
#include "lib/util/progress.h"
#include "lib/work_estimate.h"
#include "studies/engine/checkpoint.h"
#include "studies/sampling/files.h"

namespace vrv::sampling_study {

Scene ramp_scene(const Study& st) {
  Scene s = st.scene;
  s.field = st.ramp;
  return s;
}

double order_over_rates(const std::vector<double>& rates, const std::vector<double>& errors) {
  std::vector<double> steps;
  for (double r : rates) steps.push_back(1 / r);
  return estimate_order(steps, errors).order;
}

std::vector<StrategyOrder> observed_orders(const Study& st, const std::vector<StrategyRun>& runs) {
  std::vector<StrategyOrder> out;
  for (SegmentRule rule : st.rules)
  for (Strategy s : st.strategies) {
    std::vector<double> rates, max_errors, mean_errors;
    for (const StrategyRun& f : runs)
      if (f.rule == rule && f.strategy == s) {
        rates.push_back(f.rate);
        max_errors.push_back(f.stats.error.max);
        mean_errors.push_back(f.stats.error.mean);
      }
    if (*std::max_element(max_errors.begin(), max_errors.end()) <= st.identity_tol)
      out.push_back({rule, s, NAN, NAN});
    else
      out.push_back({rule, s, order_over_rates(rates, max_errors), order_over_rates(rates, mean_errors)});
  }
  return out;
}

double closed_form(const Study& st, const Ray& ray, double kappa) {
  const auto iv = clip(ray, st.scene.box);
  if (!iv) return 0;
  const PiecewiseLinear& tau = st.scene.transfer.second();
  const double phi =
      iv->length() * 0.5 * (tau(st.ramp.value(ray.at(iv->t0))) + tau(st.ramp.value(ray.at(iv->t1))));
  return -kappa * std::expm1(-phi);
}

namespace {

struct Identity {
  double max_diff = 0;
  long sample_mismatches = 0;
};

void compare(const std::vector<RayValue>& a, const std::vector<RayValue>& b, Identity& id) {
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double d = std::abs(a[i].value - b[i].value);
    id.max_diff = std::isnan(d) ? INFINITY : std::max(id.max_diff, d);
    if (a[i].samples != b[i].samples) ++id.sample_mismatches;
  }
}

// Every bound of this study follows from theory (the reasons are next to them in sampling.toml):
// tolerances of the reference, rounding allowances of exact identities, orders of first-order
// placements, and which listing keeps or drops corner rays.
StudyCheck at_most(std::string name, double value, double bound, std::string detail) {
  return {std::move(name), value, bound, value <= bound, std::move(detail), CheckKind::derived};
}
StudyCheck at_least(std::string name, double value, double bound, std::string detail) {
  return {std::move(name), value, bound, value >= bound, std::move(detail), CheckKind::derived};
}

// Each configuration's values on every ray (fan or pixels) are one checkpoint (--resume).
std::vector<ContinuousRay> continuous(const StudyRun& run, const std::string& key, const Scene& scene,
                                      const std::vector<Ray>& rays, double tol) {
  return checkpointed_records<ContinuousRay>(
      run.checkpoints, key, 3, [&] { return continuous_rays(scene, rays, tol, run.audit); },
      [](const ContinuousRay& r, std::vector<double>& out) { out.insert(out.end(), {r.chord, r.value, r.estimate}); },
      [](std::span<const double> v) { return ContinuousRay{v[0], v[1], v[2]}; }, rays.size());
}
std::vector<RayValue> discrete(Checkpoints* c, const std::string& key, const Scene& scene,
                               const std::vector<Ray>& rays, const DiscreteConfig& config) {
  return checkpointed_records<RayValue>(
      c, key, 2, [&] { return discrete_rays(scene, rays, config); },
      [](const RayValue& r, std::vector<double>& out) { out.insert(out.end(), {r.value, static_cast<double>(r.samples)}); },
      [](std::span<const double> v) { return RayValue{v[0], static_cast<long>(v[1])}; }, rays.size());
}

}  // namespace

StudyWork sampling_work(const Study& st, bool quick) {
  const Scene ramp = ramp_scene(st);
  const Vec3 eye = fan_camera(st.setup).eye;
  const Camera view = image_camera(st.setup, quick ? st.quick_width : st.width, quick ? st.quick_height : st.height);
  const double fan = st.setup.rays;
  const double pixels = static_cast<double>(view.width) * view.height;
  StudyWork work;
  work.add("fan truths (grid and ramp)", fan,
           reference_evaluations(st.scene, st.reference_tol) + reference_evaluations(ramp, st.reference_tol));
  for (SegmentRule rule : st.rules)
    for (Strategy s : st.strategies)
      for (double rate : st.order_rates)
        work.add(fmt::format("fan, {} {} at rate {:g} (grid and ramp)", segment_rule_name(rule), strategy_name(s), rate),
                 fan, discrete_samples(strategy_config(st.scene, rule, s, rate, eye), st.scene) +
                          discrete_samples(strategy_config(ramp, rule, s, rate, eye), ramp));
  work.add("image truths", pixels, reference_evaluations(st.scene, st.reference_tol));
  for (double rate : st.image_rates)
    for (Strategy s : st.strategies)
      work.add(fmt::format("images, {} at rate {:g}", strategy_name(s), rate), pixels,
               discrete_samples(strategy_config(st.scene, st.rules.front(), s, rate, view.eye), st.scene));
  return work;
}

StudyOutcome run_sampling_study(const Study& st, const StudyRun& run) {
  const Scene ramp = ramp_scene(st);
  const Camera fan = fan_camera(st.setup);
  const std::vector<Ray> fan_rays = camera_rays(fan);
  const int width = run.quick ? st.quick_width : st.width;
  const int height = run.quick ? st.quick_height : st.height;
  const Camera view = image_camera(st.setup, width, height);
  const std::vector<Ray> pixels = camera_rays(view);

  const long fan_jobs = static_cast<long>(st.rules.size() * st.strategies.size() * st.order_rates.size());
  const long image_jobs = static_cast<long>(st.strategies.size() * st.image_rates.size());
  Progress progress("sampling", 2 + fan_jobs + 1 + image_jobs, run.progress);

  // The fan: the continuous solution on the grid and on the ramp, then every configuration.
  Checkpoints* const cp = run.checkpoints;
  const std::vector<ContinuousRay> truth = continuous(run, "fan_truth", st.scene, fan_rays, st.reference_tol);
  progress.advance();
  const std::vector<ContinuousRay> truth_ramp = continuous(run, "fan_truth_ramp", ramp, fan_rays, st.reference_tol);
  progress.advance();
  double max_estimate = 0, continuous_identity = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    max_estimate = std::max({max_estimate, truth[i].estimate, truth_ramp[i].estimate});
    continuous_identity = std::max(continuous_identity, std::abs(truth[i].value - truth_ramp[i].value));
  }

  double closed_form_diff = 0;
  if (st.closed_form_kappa)
    for (std::size_t i = 0; i < truth.size(); ++i)
      closed_form_diff = std::max(
          closed_form_diff, std::abs(truth[i].value - closed_form(st, fan_rays[i], *st.closed_form_kappa)));

  Identity identity;
  long nonfinite = 0;
  std::vector<StrategyRun> runs;
  for (SegmentRule rule : st.rules)
    for (Strategy s : st.strategies)
      for (std::size_t k = 0; k < st.order_rates.size(); ++k) {
        const double rate = st.order_rates[k];
        const Vec3 eye = fan.eye;
        const std::string key = fmt::format("fan_{}_{}_{}", segment_rule_name(rule), strategy_name(s), k);
        StrategyRun f{rule, s, rate,
                      discrete(cp, key, st.scene, fan_rays, strategy_config(st.scene, rule, s, rate, eye)), {}};
        f.stats = ray_error_stats(truth, f.rays);
        nonfinite += f.stats.nonfinite;
        compare(f.rays, discrete(cp, key + "_ramp", ramp, fan_rays, strategy_config(ramp, rule, s, rate, eye)),
                identity);
        runs.push_back(std::move(f));
        progress.advance();
      }

  // The images: the continuous solution, then every strategy at every image rate.
  const std::vector<ContinuousRay> image_truth = continuous(run, "image_truth", st.scene, pixels, st.reference_tol);
  progress.advance();
  for (const ContinuousRay& c : image_truth) max_estimate = std::max(max_estimate, c.estimate);
  std::vector<StrategyRun> images;
  for (std::size_t k = 0; k < st.image_rates.size(); ++k)
    for (Strategy s : st.strategies) {
      const double rate = st.image_rates[k];
      const SegmentRule rule = st.rules.front();
      StrategyRun im{rule, s, rate,
                     discrete(cp, fmt::format("image_{}_{}", strategy_name(s), k), st.scene, pixels,
                              strategy_config(st.scene, rule, s, rate, view.eye)),
                     {}};
      im.stats = ray_error_stats(image_truth, im.rays);
      nonfinite += im.stats.nonfinite;
      images.push_back(std::move(im));
      progress.advance();
    }
  progress.finish();

  const std::vector<StrategyOrder> orders = observed_orders(st, runs);
  write_fan_tables(run.dir, st, fan_rays.size(), truth, runs, orders);
  write_images(run.dir, st, view, image_truth, images);
  write_plots(run.dir, st);

  StudyOutcome out;
  auto& checks = out.checks;
  checks.push_back(at_most("continuous solution: error estimate", max_estimate, st.reference_tol,
                           "largest error estimate of the reference over fan rays (grid and ramp) "
                           "and pixels, against its tolerance"));
  if (st.closed_form_kappa)
    checks.push_back(at_most("identity: continuous = closed form", closed_form_diff,
                             st.reference_tol + 1e-15,
                             fmt::format("g = {:g} tau: I = {:g} (1 - exp(-L (tau_in + tau_out)/2)) on "
                                         "every fan ray; tol plus the closed form's rounding",
                                         *st.closed_form_kappa, *st.closed_form_kappa)));
  checks.push_back(at_most("identity: continuous on grid = on ramp", continuous_identity,
                           2 * st.reference_tol,
                           "trilinear interpolation of a linear ramp is exact: both are within "
                           "tol of the same integral"));
  StudyCheck same = at_most("identity: discrete on grid = on ramp", identity.max_diff,
                            st.identity_tol,
                            fmt::format("every strategy and rate; sample counts differ on {} rays",
                                        identity.sample_mismatches));
  same.pass = same.pass && identity.sample_mismatches == 0;
  checks.push_back(same);
  checks.push_back(at_most("finite values", static_cast<double>(nonfinite), 0,
                           "non-finite discrete values on the fan and in the images"));
  for (const Study::OrderBound& b : st.order_bounds)
    for (Strategy s : b.strategies)
      for (const StrategyOrder& o : orders)
        if (o.rule == b.rule && o.strategy == s)
          for (const auto& [what, value] : {std::pair{"max", o.order_max}, std::pair{"mean", o.order_mean}})
            checks.push_back(at_least(
                fmt::format("order of {} error: {} {}", what, segment_rule_name(b.rule), strategy_name(s)),
                value, b.min_order, "least-squares slope of log error against log(1/rate) over orders.rates"));
  for (const Study::ExactBound& b : st.exact_bounds)
    for (Strategy s : b.strategies) {
      double worst = 0;
      for (const StrategyRun& f : runs)
        if (f.rule == b.rule && f.strategy == s) worst = std::max(worst, f.stats.error.max);
      checks.push_back(at_most(
          fmt::format("identity: {} {} = continuous", segment_rule_name(b.rule), strategy_name(s)),
          worst, b.max_error, "max error over every fan ray and rate: exact up to rounding"));
    }
  for (Strategy s : st.keeps_every_ray) {
    long dropped = 0;
    for (const StrategyRun& f : runs) dropped += f.strategy == s ? f.stats.dropped : 0;  // every rule
    for (const StrategyRun& im : images) dropped += im.strategy == s ? im.stats.dropped : 0;
    checks.push_back(at_most(fmt::format("keeps every ray: {}", strategy_name(s)),
                             static_cast<double>(dropped), 0,
                             "rays that meet the box but get no sample (fan, all rates; images)"));
  }
  for (Strategy s : st.drops_corner_rays)
    for (const StrategyRun& f : runs)
      if (f.rule == st.rules.front() && f.strategy == s && f.rate == st.curve_rates.front())
        checks.push_back(at_least(
            fmt::format("drops corner rays (Fig. 2c): {} at rate {:g}", strategy_name(s), f.rate),
            static_cast<double>(f.stats.dropped), 1,
            "fan rays that meet the box but get no sample: the paper's corner gap"));

  const auto eye = to_square_frame(st.setup, st.setup.eye);
  out.parameters = {
      {"fan_rays", fan_rays.size()},
      {"eye_in_square_frame", {eye[0], eye[1]}},
      {"fan_angle_in_square_frame_degrees", fan.angle_degrees},
      {"image_width", width},
      {"image_height", height},
      {"rays_hit", runs.empty() ? 0 : runs.front().stats.error.count},
      {"pixels_hit", images.empty() ? 0 : images.front().stats.error.count},
  };
  out.summary = fmt::format("{} rules x {} strategies x {} rates on {} rays, {}x{} images",
                            st.rules.size(), st.strategies.size(),
                            st.order_rates.size(), fan_rays.size(), width, height);
  return out;
}

}  // namespace vrv::sampling_study
