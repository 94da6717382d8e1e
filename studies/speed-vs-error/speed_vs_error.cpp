#include "studies/speed-vs-error/speed_vs_error.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <functional>
#include <memory>
#include <optional>
#include <type_traits>
#include <variant>
#include <span>

#include <fmt/format.h>

#include "lib/io/atomic_file.h"
#include "lib/discrete_raycast.h"
#include "lib/util/parallel.h"
#include "lib/util/progress.h"
#include "lib/reference_integrator.h"
#include "lib/io/table.h"
#include "lib/metrics.h"
#include "lib/order_estimate.h"
#include "lib/work_estimate.h"
#include "studies/engine/checkpoint.h"
#include "studies/engine/study_driver.h"
#include "studies/engine/study_rays.h"
#include "studies/engine/reference_audit.h"
// The truth every configuration is scored against, the reference included: the test suite's
// long-double integrator, which shares no numerical code with lib/ (its header says how).
#include "tests/lib/independent_reference.h"

namespace vrv {

std::vector<bool> pareto_front(const std::vector<double>& cost, const std::vector<double>& error) {
  const std::size_t n = cost.size();
  std::vector<bool> front(n, true);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n && front[i]; ++j) {
      const bool no_worse = cost[j] <= cost[i] && error[j] <= error[i];
      const bool better = cost[j] < cost[i] || error[j] < error[i];
      if (no_worse && better) front[i] = false;
    }
  return front;
}

std::optional<std::size_t> cheapest_reaching(const std::vector<SpeedErrorPoint>& points,
                                             const std::string& method, double target) {
  std::optional<std::size_t> best;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (points[i].method == method && points[i].max_error <= target &&
        (!best || points[i].seconds_per_ray < points[*best].seconds_per_ray))
      best = i;
  return best;
}

namespace {

constexpr long kMaxRays = 100'000;

// One configuration: the reference at `tol`, or a discrete raycast.
struct Level {
  std::string series;  // the method's `label`, else its name
  StudyMethodSpec spec;
  bool quick = true;  // part of the --quick run
};

struct Definition {
  std::string scene_toml;
  Scene scene;
  double reference_tol = 1e-13;
  std::vector<double> targets;
  std::vector<double> discrete_targets;  // of targets: some discrete method must reach these
  long repeats = 3, quick_repeats = 1;
  long count = 64, quick_count = 6;
  std::uint64_t seed = 1;
  std::vector<std::string> methods;  // in file order
  std::vector<Level> levels;         // method-major, levels in file order
};

// The method table with `key` replaced by one value of its list, read as a single method.
StudyMethodSpec one_level(const StudyReader& r, const toml::table& m, const std::string& path,
                          const Scene& scene, std::string_view key, double value) {
  toml::table copy = m;
  for (const char* list : {"steps", "quick_steps", "tols", "quick_tols"}) copy.erase(list);
  copy.insert_or_assign(key, value);
  return read_study_method(r, copy, path, scene);
}

void read_method(const StudyReader& r, const toml::table& m, const std::string& path, Definition& d) {
  const std::string name = r.string(r.require(m, "method", path), path + ".method");
  const bool reference = name == "reference";
  const char* list = reference ? "tols" : "steps";
  const char* quick_list = reference ? "quick_tols" : "quick_steps";
  static constexpr const char* kNotForReference[] = {"tol", "steps", "quick_steps"};
  static constexpr const char* kNotForDiscrete[] = {"step", "rate", "tols", "quick_tols"};
  const std::span<const char* const> wrong_keys =
      reference ? std::span<const char* const>(kNotForReference) : std::span<const char* const>(kNotForDiscrete);
  for (const char* wrong : wrong_keys)
    if (m.contains(wrong))
      r.fail(StudyReader::child(path, wrong),
             reference ? "the reference takes tols (a list)" : "discrete methods take steps (a list)");
  // Read first, so that a strategy this study does not take is named as such (not as a missing rate).
  if (!reference && m.contains("strategy"))
    read_choice<Strategy>(r, *m.get("strategy"), path + ".strategy", kWholeStepStrategies, parse_strategy, strategy_name);
  const std::vector<double> all = r.numbers(m, list, path, 1e-15, 10);
  std::vector<double> quick = m.contains(quick_list) ? r.numbers(m, quick_list, path, 1e-15, 10) : all;
  for (std::size_t i = 0; i < quick.size(); ++i)
    if (std::find(all.begin(), all.end(), quick[i]) == all.end())
      r.fail(fmt::format("{}.{}[{}]", path, quick_list, i), fmt::format("{:g} is not in {}", quick[i], list));
  const std::string series = m.contains("label") ? r.string(*m.get("label"), path + ".label") : name;
  if (std::find(d.methods.begin(), d.methods.end(), series) != d.methods.end())
    r.fail(path + (m.contains("label") ? ".label" : ".method"),
           fmt::format("'{}' is listed twice (give a distinct label)", series));
  d.methods.push_back(series);
  for (double v : all) {
    Level level{series, one_level(r, m, path, d.scene, reference ? "tol" : "step", v),
                std::find(quick.begin(), quick.end(), v) != quick.end()};
    d.levels.push_back(level);
  }
}

Definition read_definition(const StudyInput& in) {
  const StudyReader& r = in.reader;
  r.check_keys(in.doc, "", {"kind", "name", "description", "reference_tol", "targets", "discrete_targets", "repeats",
                            "quick_repeats", "scene", "rays", "method"});
  Definition d;
  d.scene = read_study_scene(r, in.doc, "", d.scene_toml);
  d.reference_tol = read_reference_tol(r, in.doc, "", d.reference_tol);
  d.targets = r.numbers(in.doc, "targets", "", 1e-14, 1);
  if (in.doc.contains("discrete_targets")) {
    d.discrete_targets = r.numbers(in.doc, "discrete_targets", "", 1e-14, 1);
    for (std::size_t i = 0; i < d.discrete_targets.size(); ++i)
      if (std::find(d.targets.begin(), d.targets.end(), d.discrete_targets[i]) == d.targets.end())
        r.fail(fmt::format("discrete_targets[{}]", i), fmt::format("{:g} is not in targets", d.discrete_targets[i]));
  }
  d.repeats = r.integer_or(in.doc, "repeats", "", 1, 100, 3);
  d.quick_repeats = r.integer_or(in.doc, "quick_repeats", "", 1, 100, 1);
  const toml::table& rays = r.table(r.require(in.doc, "rays", ""), "rays");
  r.check_keys(rays, "rays", {"count", "quick_count", "seed"});
  d.count = r.integer(r.require(rays, "count", "rays"), "rays.count", 1, kMaxRays);
  d.quick_count = r.integer_or(rays, "quick_count", "rays", 1, kMaxRays, std::min(d.count, 6L));
  d.seed = static_cast<std::uint64_t>(
      r.integer_or(rays, "seed", "rays", 0, std::numeric_limits<long>::max(), 1));
  const toml::array& methods = r.array(r.require(in.doc, "method", ""), "method");
  if (methods.empty()) r.fail("method", "no methods");
  for (std::size_t i = 0; i < methods.size(); ++i) {
    const std::string path = fmt::format("method[{}]", i);
    read_method(r, r.table(*methods.get(i), path), path, d);
  }
  return d;
}

// A configuration's row with its names and no numbers yet.
SpeedErrorPoint named_point(const Level& level) {
  SpeedErrorPoint p;
  p.method = level.series;
  p.reference = level.spec.reference;
  p.level = level.spec.reference ? level.spec.tol : level.spec.config.sampling.step;
  return p;
}

// Values and work of one configuration on every ray, in one single-threaded pass; returns the
// pass's wall time.  A discrete raycaster is built once, as a renderer would.
double one_pass(const Scene& scene, const StudyMethodSpec& spec, const std::vector<Ray>& rays,
                std::vector<double>& value, std::vector<double>& work) {
  const auto start = std::chrono::steady_clock::now();
  if (spec.reference) {
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const ReferenceResult res = integrate_reference(scene, rays[i], ReferenceOptions{spec.tol});
      value[i] = res.value;
      work[i] = static_cast<double>(res.evaluations);
    }
  } else {
    visit_field(scene, [&](const auto& field) {
      const auto caster = scene_raycaster(field, scene, spec.config);
      for (std::size_t i = 0; i < rays.size(); ++i) {
        const DiscreteResult res = caster.cast(rays[i]);
        value[i] = res.value;
        work[i] = static_cast<double>(res.samples);
      }
    });
  }
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

SpeedErrorPoint measure(const Definition& d, const Level& level, const std::vector<Ray>& rays,
                        const std::vector<double>& truth, long repeats) {
  const StudyMethodSpec& spec = level.spec;
  const std::size_t n = rays.size();
  std::vector<double> value(n), work(n);
  double best = std::numeric_limits<double>::infinity();
  for (long k = 0; k < repeats; ++k) best = std::min(best, one_pass(d.scene, spec, rays, value, work));
  SpeedErrorPoint p = named_point(level);
  p.seconds_per_ray = best / static_cast<double>(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double e = std::abs(value[i] - truth[i]);
    if (!(e <= p.max_error)) p.max_error = e;  // a NaN propagates (std::max would drop it)
    p.mean_error += e / static_cast<double>(n);
    p.work_per_ray += work[i] / static_cast<double>(n);
  }
  if (spec.reference)  // the estimate is recomputed once; it is deterministic
    for (std::size_t i = 0; i < n; ++i)
      p.max_estimate = std::max(p.max_estimate,
                                integrate_reference(d.scene, rays[i], ReferenceOptions{spec.tol}).error_estimate);
  return p;
}

// A configuration's row as one checkpoint; the names come from the study file, the numbers from the run.
SpeedErrorPoint measured(Checkpoints* checkpoints, const std::string& key, const Level& level,
                         const std::function<SpeedErrorPoint()>& run) {
  std::optional<SpeedErrorPoint> fresh;
  const std::vector<double> v = checkpointed(checkpoints, key, [&] {
    fresh = run();
    return std::vector<double>{fresh->max_error, fresh->mean_error, fresh->max_estimate, fresh->seconds_per_ray,
                               fresh->work_per_ray};
  }, 5);
  if (fresh) return *fresh;
  SpeedErrorPoint p = named_point(level);
  p.max_error = v.at(0);
  p.mean_error = v.at(1);
  p.max_estimate = v.at(2);
  p.seconds_per_ray = v.at(3);
  p.work_per_ray = v.at(4);
  return p;
}

// The field in long double for the independent integrator; nullptr for a field it does not know.
std::unique_ptr<independent::FieldLD> independent_field(const Scene& scene) {
  return std::visit(
      [](const auto& f) -> std::unique_ptr<independent::FieldLD> {
        using F = std::decay_t<decltype(f)>;
        if constexpr (std::is_same_v<F, MarschnerLobb>)
          return std::make_unique<independent::MarschnerLobbLD>(f.fM, f.alpha);
        else if constexpr (std::is_same_v<F, LinearRamp>)
          return std::make_unique<independent::LinearRampLD>(f.gradient, f.offset);
        else
          return std::make_unique<independent::GridLD>(f);
      },
      scene.field);
}

// The truth on every ray: the independent integrator's value, rounded to double.
std::vector<double> independent_truth(const Scene& scene, const std::vector<Ray>& rays, bool progress) {
  const std::unique_ptr<independent::FieldLD> field = independent_field(scene);
  std::vector<double> out(rays.size());
  Progress bar("speed-vs-error truth", static_cast<long>(rays.size()), progress);
  parallel_for_index(static_cast<long>(rays.size()), [&](long i) {
    const auto k = static_cast<std::size_t>(i);
    out[k] = static_cast<double>(
        independent::independent_integral(*field, scene.box, scene.transfer, scene.background, rays[k]).value);
    bar.advance();
  });
  bar.finish();
  return out;
}

Table points_table(const std::vector<SpeedErrorPoint>& pts, const std::vector<bool>& front_time,
                   const std::vector<bool>& front_work) {
  Table t({"method", "level_name", "level", "max_error", "mean_error", "max_estimate",
           "seconds_per_ray", "work_per_ray", "on_front", "on_work_front"});
  t.set_format("level", "{:g}");
  for (const char* c : {"max_error", "mean_error", "max_estimate", "seconds_per_ray"}) t.set_format(c, "{:.3e}");
  t.allow_missing("max_error");  // a non-finite error shows as missing and fails its check
  t.allow_missing("mean_error");
  t.set_format("work_per_ray", "{:.1f}");
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const SpeedErrorPoint& p = pts[i];
    t.add_row({p.method, p.level_name(), p.level, p.max_error, p.mean_error, p.max_estimate,
               p.seconds_per_ray, p.work_per_ray, std::string(front_time[i] ? "true" : "false"),
               std::string(front_work[i] ? "true" : "false")});
  }
  return t;
}

Table targets_table(const Definition& d, const std::vector<SpeedErrorPoint>& pts) {
  Table t({"target", "method", "level", "max_error", "seconds_per_ray", "work_per_ray",
           "cost_vs_fastest", "fastest"});
  for (const char* c : {"level", "max_error", "seconds_per_ray", "work_per_ray", "cost_vs_fastest"})
    t.allow_missing(c);
  t.set_format("target", "{:g}");
  t.set_format("level", "{:g}");
  t.set_format("max_error", "{:.2e}");
  t.set_format("seconds_per_ray", "{:.3e}");
  t.set_format("work_per_ray", "{:.1f}");
  t.set_format("cost_vs_fastest", "{:.1f}");
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  for (double target : d.targets) {
    double fastest = std::numeric_limits<double>::infinity();
    for (const std::string& m : d.methods)
      if (const auto i = cheapest_reaching(pts, m, target)) fastest = std::min(fastest, pts[*i].seconds_per_ray);
    for (const std::string& m : d.methods) {
      const auto i = cheapest_reaching(pts, m, target);
      if (!i) {
        t.add_row({target, m, nan, nan, nan, nan, nan, std::string("not reached")});
        continue;
      }
      const SpeedErrorPoint& p = pts[*i];
      t.add_row({target, m, p.level, p.max_error, p.seconds_per_ray, p.work_per_ray,
                 p.seconds_per_ray / fastest, std::string(p.seconds_per_ray == fastest ? "yes" : "")});
    }
  }
  return t;
}

constexpr const char* kPlots = R"json({
  "plots": [
    {"name": "speed_vs_error", "csv": "points.csv", "style": "lines", "x": "seconds_per_ray",
     "y": "max_error", "group": "method", "xscale": "log", "yscale": "log", "front": true,
     "hlines": [1e-3, 1e-6], "xlabel": "time per ray (s, one thread, best of repeats)",
     "ylabel": "max |value - reference| over the rays", "title": "Speed against error"},
    {"name": "work_vs_error", "csv": "points.csv", "style": "lines", "x": "work_per_ray",
     "y": "max_error", "group": "method", "xscale": "log", "yscale": "log", "fit": true,
     "hlines": [1e-3, 1e-6], "xlabel": "field evaluations (reference) or samples per ray",
     "ylabel": "max |value - reference| over the rays", "title": "Work against error"}
  ]
}
)json";

// The independent truth against the reference at reference_tol, ray by ray.
struct TruthCheck {
  double max_difference = 0;  // max |reference - truth|
  double bound = 0;           // the reference's largest estimate + rounding
  double rounding = 0;        // the truth's own error: rounding to double (2 eps |value|), largest
};

TruthCheck compare_truth(const std::vector<double>& truth, const std::vector<ReferenceResult>& reference) {
  TruthCheck c;
  double estimate = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const double diff = std::abs(reference[i].value - truth[i]);
    if (!(diff <= c.max_difference)) c.max_difference = diff;  // NaN propagates
    estimate = std::max(estimate, reference[i].error_estimate);
    // Long double to double rounds by half an ulp; the integral itself agrees with finer
    // settings of its own to ~1e-18 (test_reference_integrator.cpp), far below.
    c.rounding = std::max(c.rounding, 2 * std::numeric_limits<double>::epsilon() * std::abs(truth[i]));
  }
  c.bound = estimate + c.rounding;
  return c;
}

std::vector<StudyCheck> checks_of(const Definition& d, const std::vector<SpeedErrorPoint>& pts,
                                  const TruthCheck& truth) {
  // By what a series is, not by its name (a label may rename the reference).
  const auto reference_series = [&](const std::string& m) {
    return std::any_of(pts.begin(), pts.end(), [&](const SpeedErrorPoint& p) { return p.method == m && p.reference; });
  };
  std::vector<StudyCheck> checks;
  checks.push_back({fmt::format("truth: reference tol={:g} agrees with the independent integrator", d.reference_tol),
                    truth.max_difference, truth.bound, truth.max_difference <= truth.bound,
                    "max |reference - independent long-double integral| over the rays <= the reference's largest "
                    "estimate + the truth's rounding",
                    CheckKind::derived});
  for (const SpeedErrorPoint& p : pts) {
    if (p.reference) {
      const double bound = p.max_estimate + truth.rounding;
      checks.push_back({fmt::format("{} tol={:g}: error within its estimate", p.method, p.level), p.max_error, bound,
                        p.max_error <= bound,
                        "max error against the independent truth <= largest own estimate + the truth's rounding",
                        CheckKind::derived});
      checks.push_back({fmt::format("{} tol={:g}: meets its tolerance", p.method, p.level), p.max_estimate,
                        p.level, p.max_estimate <= p.level, "largest own error estimate <= tol", CheckKind::derived});
    }
    const bool finite = std::isfinite(p.max_error) && std::isfinite(p.mean_error) &&
                        std::isfinite(p.seconds_per_ray) && p.seconds_per_ray > 0;
    if (!finite)
      checks.push_back({fmt::format("{} {}={:g}: finite", p.method, p.level_name(), p.level), p.max_error, 0,
                        false, "error and time finite, time > 0", CheckKind::derived});
  }
  // Convergence, loosely (the convergence study checks orders): the least-squares slope of
  // log max error against log step is at least 1/2.  Max errors of sample rules jump with where
  // the exit falls in the last step, so a two-point ratio would be too noisy to gate on.
  for (const std::string& m : d.methods) {
    std::vector<double> steps, errors;
    for (const SpeedErrorPoint& p : pts)
      if (p.method == m && !p.reference) {
        steps.push_back(p.level);
        errors.push_back(p.max_error);
      }
    if (steps.size() < 2) continue;  // the reference, or a single level
    const double order = estimate_order(steps, errors).order;
    checks.push_back({fmt::format("{}: converges", m), order, 0.5, order >= 0.5,
                      "observed order of the max error over the steps >= 1/2 (a floor on any consistent rule; "
                      "the convergence study gates the orders)",
                      CheckKind::derived});
  }
  // Each target, scored against the independent truth: the reference at the loosest tolerance
  // <= target must reach it (its promise), and the discrete methods are gated as a regression.
  for (double target : d.targets) {
    std::optional<std::size_t> ref;
    for (std::size_t i = 0; i < pts.size(); ++i)
      if (pts[i].reference && pts[i].level <= target && (!ref || pts[i].level > pts[*ref].level)) ref = i;
    if (ref)
      checks.push_back({fmt::format("target {:g}: {} tol={:g} reaches it", target, pts[*ref].method, pts[*ref].level),
                        pts[*ref].max_error, target, pts[*ref].max_error <= target,
                        "max error against the independent truth <= target (the tolerance it was asked for)",
                        CheckKind::derived});
    if (std::find(d.discrete_targets.begin(), d.discrete_targets.end(), target) == d.discrete_targets.end()) continue;
    std::string by;
    for (const std::string& m : d.methods)
      if (!reference_series(m) && cheapest_reaching(pts, m, target)) by += (by.empty() ? "" : ", ") + m;
    checks.push_back({fmt::format("target {:g}: reached by a discrete method", target),
                      by.empty() ? 0.0 : 1.0, 1.0, !by.empty(),
                      by.empty() ? std::string("no discrete method reaches max error <= target")
                                 : "reached by " + by + " (against the independent truth)",
                      CheckKind::regression});
  }
  return checks;
}

// The independent truth's long-double evaluations on the box's diagonal, from its options
// (tests/lib/independent_reference.h): the scan for extrema, then per panel the outer rule's
// depth, its nodes, and the nested depth at each node; refinements left out.
double independent_evaluations(const Scene& scene) {
  const independent::Options o;
  const double length = scene.box.extent().norm();
  const double scan = std::max(16.0, std::ceil(static_cast<double>(o.scan_density) * length));
  const double panels = std::ceil(length / static_cast<double>(o.max_panel));
  return scan + panels * o.points * (2 + o.inner_points);
}

// Every configuration is cast `repeats` times (the reference once more for its estimates).
StudyWork study_work(const Definition& d, bool quick) {
  const double n = static_cast<double>(quick ? d.quick_count : d.count);
  const double repeats = static_cast<double>(quick ? d.quick_repeats : d.repeats);
  StudyWork work;
  work.add("reference truths", n, reference_evaluations(d.scene, d.reference_tol));
  work.add("independent truths (long double)", n, independent_evaluations(d.scene));
  for (const Level& level : d.levels) {
    if (quick && !level.quick) continue;
    const StudyMethodSpec& spec = level.spec;
    work.add(method_label(spec), n,
             spec.reference ? (repeats + 1) * reference_evaluations(d.scene, spec.tol)
                            : repeats * discrete_samples(spec.config, d.scene));
  }
  return work;
}

StudyPlan parse_speed_vs_error(const StudyInput& in) {
  Definition d = read_definition(in);
  StudyJob job = [d](const StudyRun& run) {
    const long n = run.quick ? d.quick_count : d.count;
    const std::vector<Ray> rays = study_rays(d.scene.box, n, d.seed);
    // Checkpoints (--resume): the reference on every ray, the truth, each configuration's row
    // (its time included: a resumed run reports the time measured when the row was computed).
    const std::vector<ReferenceResult> truth = checkpointed_records<ReferenceResult>(
        run.checkpoints, "reference", 2,
        [&] {
          std::vector<ReferenceResult> t(static_cast<std::size_t>(n));
          parallel_for_index(n, [&](long i) {
            t[static_cast<std::size_t>(i)] =
                audited_reference(run.audit, d.scene, rays[static_cast<std::size_t>(i)], ReferenceOptions{d.reference_tol});
          });
          return t;
        },
        [](const ReferenceResult& r, std::vector<double>& out) { out.insert(out.end(), {r.value, r.error_estimate}); },
        [](std::span<const double> v) {
          ReferenceResult r;
          r.value = v[0];
          r.error_estimate = v[1];
          return r;
        },
        rays.size());
    double truth_estimate = 0;
    for (const ReferenceResult& t : truth) truth_estimate = std::max(truth_estimate, t.error_estimate);
    const std::vector<double> independent =
        checkpointed(run.checkpoints, "truth", [&] { return independent_truth(d.scene, rays, run.progress); },
                     rays.size());
    const TruthCheck truth_check = compare_truth(independent, truth);
    std::vector<SpeedErrorPoint> pts;
    Progress progress("speed-vs-error", static_cast<long>(d.levels.size()), run.progress);
    for (std::size_t k = 0; k < d.levels.size(); ++k) {  // one at a time: the timings must not share the cores
      const Level& level = d.levels[k];
      if (!run.quick || level.quick)
        pts.push_back(measured(run.checkpoints, fmt::format("level_{}", k), level, [&] {
          return measure(d, level, rays, independent, run.quick ? d.quick_repeats : d.repeats);
        }));
      progress.advance();
    }
    progress.finish();
    std::vector<double> time, work, error;
    for (const SpeedErrorPoint& p : pts) {
      time.push_back(p.seconds_per_ray);
      work.push_back(p.work_per_ray);
      error.push_back(p.max_error);
    }
    const Table points = points_table(pts, pareto_front(time, error), pareto_front(work, error));
    const Table targets = targets_table(d, pts);
    LatexStyle style;
    style.caption = fmt::format("Cheapest configuration of each method reaching each target max error "
                                "({} rays; one thread; times are this machine's).", n);
    style.label = "tab:speed-vs-error";
    write_file_atomically(run.dir / "points.csv", points.to_csv());
    write_file_atomically(run.dir / "points.md", points.to_markdown());
    write_file_atomically(run.dir / "targets.csv", targets.to_csv());
    write_file_atomically(run.dir / "targets.md", targets.to_markdown());
    write_file_atomically(run.dir / "targets.tex", targets.to_latex(style));
    write_file_atomically(run.dir / "plots.json", kPlots);
    StudyOutcome out;
    out.checks = checks_of(d, pts, truth_check);
    std::string load;
    if (std::ifstream f("/proc/loadavg"); f) std::getline(f, load);
    out.parameters = {{"rays", n}, {"repeats", run.quick ? d.quick_repeats : d.repeats},
                      {"configurations", pts.size()}, {"loadavg_after", load},
                      {"truth", "independent long-double integrator (tests/independent_reference.h)"},
                      {"reference_max_estimate", truth_estimate},
                      {"reference_max_difference_from_truth", truth_check.max_difference}};
    out.summary = fmt::format("{} configurations on {} rays", pts.size(), n);
    return out;
  };
  return {std::move(job), [d](bool quick) { return study_work(d, quick); }};
}

const RegisterStudyKind kSpeedVsError{"speed_vs_error", parse_speed_vs_error};

}  // namespace
}  // namespace vrv
