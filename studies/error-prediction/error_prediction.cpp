#include "studies/error-prediction/error_prediction.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include <fmt/format.h>

#include "lib/discrete_error_bound.h"
#include "lib/discrete_error_estimate.h"
#include "lib/sampling.h"
#include "lib/io/atomic_file.h"
#include "lib/io/table.h"
#include "lib/study_file.h"
#include "lib/util/task_rows.h"
#include "lib/work_estimate.h"
#include "studies/engine/checkpoint.h"
#include "studies/engine/reference_audit.h"
#include "studies/engine/study_rays.h"
#include "studies/engine/study_outputs.h"

namespace vrv {
namespace {

// Errors and scales below this are rounding (and the reference's reach, 1e-13), not the rule's: no
// relative miss is taken of them (the jumps case's alpha rays are exact but for rounding).
constexpr double kMeasurable = 1e-11;

ErrorPredictionCase read_case(const StudyReader& r, const toml::table& t, const std::string& path) {
  r.check_keys(t, path, {"name", "scene", "steps", "quick_steps"});
  ErrorPredictionCase c;
  c.name = r.string(r.require(t, "name", path), path + ".name");
  std::string text;
  c.scene = read_study_scene(r, t, path, text);
  c.steps = r.numbers(t, "steps", path, 1e-9, 1e9);
  c.quick_steps = t.contains("quick_steps") ? r.numbers(t, "quick_steps", path, 1e-9, 1e9) : c.steps;
  return c;
}

DiscreteConfig config_of(const ErrorPredictionCase& c, SegmentRule rule, Strategy strategy, double step) {
  DiscreteConfig config;
  config.rule = rule;
  config.sampling.strategy = strategy;
  config.sampling.step = step;
  config.sampling.dims = c.scene.dims;
  return config;
}

// The method at this step of the case (its grid's dims for rate-based options).
DiscreteConfig configured(const ErrorPredictionCase& c, const PredictionMethod& m, double step) {
  DiscreteConfig config = m.config;
  config.sampling.step = step;
  config.sampling.dims = c.scene.dims;
  return config;
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size())))];
}

// |estimate - measured| / scale, of the rays of one class.
std::vector<double> scale_misses(const std::vector<PredictionConfig>& configs, bool asymptotic) {
  std::vector<double> out;
  for (const PredictionConfig& c : configs)
    for (const PredictionRay& r : c.rays)
      if (r.asymptotic == asymptotic && r.scale > kMeasurable) out.push_back(std::abs(r.estimated - r.measured) / r.scale);
  return out;
}

// Rays whose measured error exceeds the bound (by more than the reference's own estimate).
long bound_violations(const PredictionConfig& c) {
  return std::count_if(c.rays.begin(), c.rays.end(), [](const PredictionRay& r) {
    return !(std::abs(r.measured) <= r.bound + r.reference_estimate);
  });
}

}  // namespace

// A [[variant]]: a method as study files write one (lib/study_file.h: method, strategy and the
// options), with a label and without a step (the cases' steps are used).
PredictionMethod read_variant(const StudyReader& r, const toml::table& t, const std::string& path, const Scene& scene) {
  for (const char* key : {"step", "rate", "tol", "max_error"})
    if (t.contains(key)) r.fail(path + "." + key, "not a variant's: the cases' steps are used, the truth is the reference's");
  if (!t.contains("label")) r.fail(path + ".label", "required: names the variant in the tables");
  // Read first, so that a strategy this study does not take is named as such (not as a missing rate).
  if (t.contains("strategy"))
    read_choice<Strategy>(r, *t.get("strategy"), path + ".strategy", kWholeStepStrategies, parse_strategy, strategy_name);
  toml::table with_step = t;
  with_step.insert_or_assign("step", 1.0);  // replaced by each case's steps
  const StudyMethodSpec spec = read_study_method(r, with_step, path, scene);
  if (spec.reference) r.fail(path + ".method", "a discrete method (the reference is the truth)");
  return {spec.label, spec.config};
}

ErrorPredictionStudy read_error_prediction_study(const StudyInput& in) {
  const StudyReader& r = in.reader;
  const toml::table& doc = in.doc;
  r.check_keys(doc, "", {"name", "kind", "description", "reference_tol", "rays", "quick_rays", "seed", "rules",
                         "strategies", "variant", "asymptotic_miss", "separation", "case"});
  ErrorPredictionStudy s;
  s.reference_tol = read_reference_tol(r, doc, "", s.reference_tol);
  s.rays = r.integer_or(doc, "rays", "", 1, 100000, s.rays);
  s.quick_rays = r.integer_or(doc, "quick_rays", "", 1, 100000, s.quick_rays);
  s.seed = static_cast<std::uint64_t>(r.integer_or(doc, "seed", "", 0, 1L << 40, 29));
  s.asymptotic_miss = r.number_or(doc, "asymptotic_miss", "", s.asymptotic_miss);
  if (!(s.asymptotic_miss > 0)) r.fail("asymptotic_miss", "must be positive");
  s.separation = r.number_or(doc, "separation", "", s.separation);
  if (!(s.separation > 0)) r.fail("separation", "must be positive");
  const auto rules = read_choices(r, doc, "rules", "", all_segment_rules(), parse_segment_rule, segment_rule_name);
  const auto strategies =
      read_choices<Strategy>(r, doc, "strategies", "", kWholeStepStrategies, parse_strategy, strategy_name);
  const toml::array& cases = r.array(r.require(doc, "case", ""), "case");
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const std::string path = fmt::format("case[{}]", i);
    s.cases.push_back(read_case(r, r.table(*cases.get(i), path), path));
  }
  if (s.cases.empty()) r.fail("case", "at least one [[case]]");
  for (SegmentRule rule : rules)
    for (Strategy st : strategies)
      s.methods.push_back({fmt::format("{} {}", segment_rule_name(rule), strategy_name(st)),
                           config_of(s.cases.front(), rule, st, 1)});
  if (doc.contains("variant")) {
    const toml::array& variants = r.array(*doc.get("variant"), "variant");
    for (std::size_t i = 0; i < variants.size(); ++i) {
      const std::string path = fmt::format("variant[{}]", i);
      s.methods.push_back(read_variant(r, r.table(*variants.get(i), path), path, s.cases.front().scene));
    }
  }
  // Every configuration must be one the estimate and the bound cover, on every case: said now.
  for (std::size_t i = 0; i < s.cases.size(); ++i)
    for (const PredictionMethod& m : s.methods) {
      const ErrorPredictionCase& c = s.cases[i];
      const DiscreteConfig config = configured(c, m, c.steps.front());
      try {
        validate(config, std::holds_alternative<GridField>(c.scene.field), c.scene.transfer);
      } catch (const std::invalid_argument& e) {
        r.fail(fmt::format("case[{}]", i), fmt::format("{}: {}", m.label, e.what()));
      }
      if (const std::string why = why_no_error_bound(c.scene, config); !why.empty())
        r.fail(fmt::format("case[{}]", i), fmt::format("{}: no estimate is made for {} (docs/error-bounds.md)", m.label, why));
    }
  return s;
}

ErrorPredictionResult run_error_prediction(const ErrorPredictionStudy& study, const StudyRun& run) {
  const bool quick = run.quick;
  Checkpoints* checkpoints = run.checkpoints;
  ErrorPredictionResult out;
  out.rays = quick ? study.quick_rays : study.rays;
  constexpr std::size_t kWidth = 6;
  for (const ErrorPredictionCase& c : study.cases) {
    const std::vector<Ray> rays = study_rays(c.scene.box, out.rays, study.seed);
    const std::vector<double> truth = checkpointed(checkpoints, c.name + ".truth", [&] {
      return task_rows(out.rays, 2, [&](long i, std::span<double> row) {
        const ReferenceResult ref = audited_reference(run.audit, c.scene, rays[i], {study.reference_tol});
        row[0] = ref.value, row[1] = ref.error_estimate;
      }, task_block(out.rays));
    }, 2 * rays.size());
    for (std::size_t j = 0; j < study.methods.size(); ++j)
        for (double step : quick ? c.quick_steps : c.steps) {
          const PredictionMethod& m = study.methods[j];
          PredictionConfig p{c.name, m.label, configured(c, m, step), {}};
          const std::string key = fmt::format("{}.method{}.{}", c.name, j, step);  // labels may hold any text
          p.rays = checkpointed_records<PredictionRay>(
              checkpoints, key, kWidth,
              [&] {
                return task_values(out.rays, [&](long i) {
                  const Ray& ray = rays[i];
                  const DiscreteErrorEstimate e = estimate_discrete_error(c.scene, ray, p.config);
                  return PredictionRay{discrete_raycast(c.scene, ray, p.config).value - truth[2 * i], e.error,
                                       discrete_error_bound(c.scene, ray, p.config).bound, e.scale, e.asymptotic,
                                       truth[2 * i + 1]};
                });
              },
              [](const PredictionRay& r, std::vector<double>& flat) {
                flat.insert(flat.end(), {r.measured, r.estimated, r.bound, r.scale, r.asymptotic ? 1.0 : 0.0,
                                         r.reference_estimate});
              },
              [](std::span<const double> v) { return PredictionRay{v[0], v[1], v[2], v[3], v[4] != 0, v[5]}; },
              rays.size());
          out.configs.push_back(std::move(p));
        }
  }
  return out;
}

namespace {

constexpr const char* kPlots = R"json({
  "plots": [
    {"name": "predicted_vs_measured", "csv": "rays.csv", "style": "points", "x": "measured_abs", "y": "estimated_abs",
     "group": "class", "xscale": "log", "yscale": "log", "diagonal": true,
     "xlabel": "measured |discrete - reference|", "ylabel": "estimated |discrete - reference|",
     "title": "The estimate against the measured error, per ray"},
    {"name": "bound_vs_measured", "csv": "rays.csv", "style": "points", "x": "measured_abs", "y": "bound",
     "group": "case", "xscale": "log", "yscale": "log", "diagonal": true,
     "xlabel": "measured |discrete - reference|", "ylabel": "a-priori bound",
     "title": "The a-priori bound against the measured error, per ray"}
  ]
}
)json";

const char* class_name(bool asymptotic) { return asymptotic ? "asymptotic" : "not asymptotic"; }

Table rays_table(const ErrorPredictionResult& result) {
  Table t({"case", "method", "step", "ray", "measured", "estimated", "bound", "scale", "class", "measured_abs",
           "estimated_abs"});
  for (const PredictionConfig& c : result.configs)
    for (std::size_t i = 0; i < c.rays.size(); ++i) {
      const PredictionRay& r = c.rays[i];
      t.add_row({c.case_name, c.method, c.config.sampling.step, static_cast<long>(i),
                 r.measured, r.estimated, r.bound, r.scale, std::string(class_name(r.asymptotic)),
                 std::abs(r.measured), std::abs(r.estimated)});
    }
  return t;
}

Table summary_table(const ErrorPredictionResult& result) {
  Table t({"case", "method", "step", "rays", "asymptotic", "miss_of_error_median", "miss_of_scale_p90",
           "bound_ratio_min", "bound_ratio_median", "bound_below"});
  for (const char* c : {"miss_of_error_median", "miss_of_scale_p90", "bound_ratio_min", "bound_ratio_median"}) {
    t.allow_missing(c);
    t.set_format(c, "{:.3g}");
  }
  for (const PredictionConfig& c : result.configs) {
    std::vector<double> of_error, of_scale, ratio;
    long asymptotic = 0;
    for (const PredictionRay& r : c.rays) {
      asymptotic += r.asymptotic;
      const double miss = std::abs(r.estimated - r.measured);
      if (r.scale > kMeasurable) of_scale.push_back(miss / r.scale);
      if (std::abs(r.measured) > kMeasurable) {
        of_error.push_back(miss / std::abs(r.measured));
        ratio.push_back(r.bound / std::abs(r.measured));
      }
    }
    t.add_row({c.case_name, c.method, c.config.sampling.step,
               static_cast<long>(c.rays.size()), asymptotic, quantile(of_error, 0.5), quantile(of_scale, 0.9),
               ratio.empty() ? NAN : *std::min_element(ratio.begin(), ratio.end()), quantile(ratio, 0.5),
               bound_violations(c)});
  }
  return t;
}

// Per case or per method (`by`): how many rays are asymptotic, the estimate's miss on them, the
// bound's looseness.
Table grouped_table(const ErrorPredictionResult& result, const std::string& by) {
  const auto key = [&](const PredictionConfig& c) { return by == "case" ? c.case_name : c.method; };
  Table t({by, "rays", "asymptotic", "miss_of_scale_p90", "miss_of_scale_p99", "bound_ratio_median",
           "bound_ratio_p90", "bound_below"});
  for (const char* c : {"miss_of_scale_p90", "miss_of_scale_p99", "bound_ratio_median", "bound_ratio_p90"}) {
    t.allow_missing(c);
    t.set_format(c, "{:.3g}");
  }
  std::vector<std::string> names;
  for (const PredictionConfig& c : result.configs)
    if (std::find(names.begin(), names.end(), key(c)) == names.end()) names.push_back(key(c));
  for (const std::string& name : names) {
    std::vector<PredictionConfig> of;
    std::copy_if(result.configs.begin(), result.configs.end(), std::back_inserter(of),
                 [&](const PredictionConfig& c) { return key(c) == name; });
    long rays = 0, asymptotic = 0, below = 0;
    std::vector<double> ratio;
    for (const PredictionConfig& c : of) {
      below += bound_violations(c);
      for (const PredictionRay& r : c.rays) {
        ++rays;
        asymptotic += r.asymptotic;
        if (std::abs(r.measured) > kMeasurable) ratio.push_back(r.bound / std::abs(r.measured));
      }
    }
    const std::vector<double> m = scale_misses(of, true);
    t.add_row({name, rays, asymptotic, quantile(m, 0.9), quantile(m, 0.99), quantile(ratio, 0.5), quantile(ratio, 0.9),
               below});
  }
  return t;
}

Table classes_table(const ErrorPredictionResult& result) {
  Table t({"class", "rays", "miss_of_scale_p50", "miss_of_scale_p90", "miss_of_scale_p99", "miss_of_scale_max"});
  for (const char* c : {"miss_of_scale_p50", "miss_of_scale_p90", "miss_of_scale_p99", "miss_of_scale_max"}) {
    t.allow_missing(c);
    t.set_format(c, "{:.3g}");
  }
  for (bool asymptotic : {true, false}) {
    const std::vector<double> m = scale_misses(result.configs, asymptotic);
    t.add_row({std::string(class_name(asymptotic)), static_cast<long>(m.size()), quantile(m, 0.5), quantile(m, 0.9),
               quantile(m, 0.99), m.empty() ? NAN : *std::max_element(m.begin(), m.end())});
  }
  return t;
}

}  // namespace

void write_error_prediction(const std::filesystem::path& dir, const ErrorPredictionResult& result) {
  write_file_atomically(dir / "rays.csv", rays_table(result).to_csv());
  LatexStyle style;
  style.caption = "Predicted against measured error per configuration";
  style.label = "tab:error-prediction";
  write_table(dir, "summary", summary_table(result), style);
  style.caption = "The estimate's miss against the ray's error scale, by the asymptotic flag";
  style.label = "tab:error-prediction-classes";
  write_table(dir, "classes", classes_table(result), style);
  style.caption = "Per case: asymptotic rays, the estimate's miss on them, the bound over the measured error";
  style.label = "tab:error-prediction-cases";
  write_table(dir, "cases", grouped_table(result, "case"), style);
  style.caption = "Per method: asymptotic rays, the estimate's miss on them, the bound over the measured error";
  style.label = "tab:error-prediction-methods";
  write_table(dir, "methods", grouped_table(result, "method"), style);
  write_file_atomically(dir / "plots.json", kPlots);
}

std::vector<StudyCheck> error_prediction_checks(const ErrorPredictionStudy& study, const ErrorPredictionResult& result) {
  std::vector<StudyCheck> checks;
  long below = 0, rays = 0, non_finite = 0;
  for (const PredictionConfig& c : result.configs) {
    below += bound_violations(c);
    rays += static_cast<long>(c.rays.size());
    for (const PredictionRay& r : c.rays)
      non_finite += !std::isfinite(r.estimated) || !std::isfinite(r.bound) || !std::isfinite(r.scale);
  }
  checks.push_back({"bound never below the measured error", static_cast<double>(below), 0, below == 0,
                    fmt::format("rays of {} whose |discrete - reference| exceeds the a-priori bound plus the "
                                "reference's estimate", rays),
                    CheckKind::derived});
  checks.push_back({"predictions finite", static_cast<double>(non_finite), 0, non_finite == 0,
                    "rays whose estimate, bound or scale is not finite", CheckKind::derived});
  const std::vector<double> flagged = scale_misses(result.configs, true), others = scale_misses(result.configs, false);
  const double p99 = quantile(flagged, 0.99);
  checks.push_back({"estimate within its scale on asymptotic rays", p99, study.asymptotic_miss,
                    !flagged.empty() && p99 <= study.asymptotic_miss,
                    fmt::format("99th percentile of |estimate - measured| / scale over {} asymptotic rays",
                                flagged.size()),
                    CheckKind::regression});
  if (!others.empty()) {
    // A floor of one rounding unit keeps the ratio finite where every asymptotic ray is met exactly.
    const double ratio = quantile(others, 0.9) / std::max(quantile(flagged, 0.9), 1e-16);
    checks.push_back({"the asymptotic flag separates the rays", ratio, study.separation, ratio >= study.separation,
                      fmt::format("90th percentile of the miss of scale: {} rays not asymptotic over {} asymptotic "
                                  "(at least the bound)", others.size(), flagged.size()),
                      CheckKind::regression});
  }
  return checks;
}

StudyWork error_prediction_work(const ErrorPredictionStudy& study, bool quick) {
  StudyWork work;
  const double rays = static_cast<double>(quick ? study.quick_rays : study.rays);
  for (const ErrorPredictionCase& c : study.cases) {
    work.add(c.name + " references", rays, reference_evaluations(c.scene, study.reference_tol));
    for (const PredictionMethod& m : study.methods)
      for (double step : quick ? c.quick_steps : c.steps) {
        const DiscreteConfig config = configured(c, m, step);
        // The raycast, then the estimate's and the bound's proxies per segment and their casts.
        work.add(fmt::format("{} {} h = {:g}", c.name, m.label, step), rays,
                 discrete_samples(analysed_configuration(config), c.scene) * kPredictedRaycastWorkFactor);
      }
  }
  return work;
}

}  // namespace vrv
