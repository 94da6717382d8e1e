// vrv demo: what vrv is for, in one screen.  On the embedded default scene (or --scene), a fixed
// set of rays: the reference integral per ray with its cost and error estimate, and every segment
// rule's mean error against it at a few halvings of the step, with its observed order of
// convergence against the expected one.  The pieces are the studies' own: study_rays (the ray
// set), estimate_order and order_matches (the least-squares slope and the band the studies check
// it in, lib/order_estimate.h) and the table writer.
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "lib/discrete_raycast.h"
#include "lib/io/table.h"
#include "lib/order_estimate.h"
#include "lib/reference_integrator.h"
#include "lib/util/parallel.h"
#include "studies/cli/cli_support.h"
#include "studies/cli/memory_limit.h"
#include "studies/cli/discrete_flags.h"
#include "studies/cli/commands.h"
#include "studies/engine/study_rays.h"

namespace vrv::cli {
namespace {

struct DemoOptions {
  std::string scene;     // scene file; the embedded default when empty
  std::optional<double> max_memory_gib;  // --max-memory: the scene's volume
  int rays = 64;         // rays of the fixed-seed study set (seed 1)
  double tol = ReferenceOptions{}.tol;  // the reference's absolute tolerance on I
  double step = 0.01;    // the coarsest step (world units); each next one is half of it
  int halvings = 3;      // steps: step, step/2, ..., step/2^halvings
  // |observed - expected| <= max(margin * c_1 * SE, floor): the convergence study's band.
  OrderTolerance order_tolerance{.margin = 2, .floor = 0.05};
};

// The expected orders (theory; studies/convergence/convergence.toml states the same): Riemann's
// eq. (5) is first order; the alpha rule with midpoint samples, trapezoid, exact_linear and
// Moreland's average opacity are second order.
struct RuleOrder {
  SegmentRule rule;
  double expected;
};
constexpr RuleOrder kRules[] = {{SegmentRule::riemann, 1},
                                {SegmentRule::alpha, 2},
                                {SegmentRule::trapezoid, 2},
                                {SegmentRule::exact_linear, 2},
                                {SegmentRule::moreland, 2}};
constexpr std::size_t kRuleCount = std::size(kRules);

void check(const DemoOptions& opt) {
  check_tolerance(opt.tol);
  if (opt.rays < 1 || opt.rays > 100000)
    throw std::invalid_argument(fmt::format("--rays: must be in [1, 100000], got {}", opt.rays));
  if (!(opt.step > 0) || !std::isfinite(opt.step))
    throw std::invalid_argument(fmt::format("--step: must be positive, got {}", opt.step));
  // Three steps at least: the order's band is derived from the fit's spread.
  if (opt.halvings < 2 || opt.halvings > 8)
    throw std::invalid_argument(fmt::format("--halvings: must be in [2, 8], got {}", opt.halvings));
}

struct DemoRun {
  std::vector<double> steps;
  std::vector<ReferenceResult> reference;  // per ray
  std::vector<double> mean_error;          // [rule][step]
  std::vector<double> samples_per_ray;     // [rule][step]
};

// Every ray's reference and discrete values into their own slots, then means in ray order: the
// same bits for any thread count.
DemoRun run(const Scene& scene, const DemoOptions& opt) {
  DemoRun out;
  for (int k = 0; k <= opt.halvings; ++k) out.steps.push_back(std::ldexp(opt.step, -k));
  const std::size_t S = out.steps.size(), per_ray = kRuleCount * S;
  std::vector<DiscreteConfig> configs;
  for (const RuleOrder& r : kRules)
    for (double h : out.steps) {
      DiscreteConfig c;
      c.rule = r.rule;
      c.sampling.strategy = Strategy::inviwo;
      c.sampling.step = h;
      c.sampling.dims = scene.dims;
      configs.push_back(c);
    }
  const std::vector<Ray> rays = study_rays(scene.box, opt.rays, 1);
  const std::size_t n = rays.size();
  out.reference.resize(n);
  std::vector<double> error(n * per_ray), samples(n * per_ray);
  parallel_for_index(static_cast<long>(n), [&](long li) {
    const std::size_t i = static_cast<std::size_t>(li);
    out.reference[i] = integrate_reference(scene, rays[i], {opt.tol});
    for (std::size_t k = 0; k < per_ray; ++k) {
      const DiscreteResult d = discrete_raycast(scene, rays[i], configs[k]);
      error[i * per_ray + k] = std::abs(d.value - out.reference[i].value);
      samples[i * per_ray + k] = static_cast<double>(d.samples);
    }
  });
  out.mean_error.assign(per_ray, 0);
  out.samples_per_ray.assign(per_ray, 0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = 0; k < per_ray; ++k) {
      out.mean_error[k] += error[i * per_ray + k] / static_cast<double>(n);
      out.samples_per_ray[k] += samples[i * per_ray + k] / static_cast<double>(n);
    }
  return out;
}

Table error_table(const DemoRun& r, const DemoOptions& opt) {
  std::vector<std::string> columns{"rule"};
  for (double h : r.steps) columns.push_back(fmt::format("h={:g}", h));
  for (const char* c : {"expected", "observed", "ok"}) columns.push_back(c);
  Table t(columns);
  for (std::size_t s = 0; s < r.steps.size(); ++s) t.set_format(columns[1 + s], "{:.2e}");
  t.set_format("expected", "{:g}");
  t.set_format("observed", "{:.2f}");
  t.allow_missing("observed");
  const std::size_t S = r.steps.size();
  for (std::size_t m = 0; m < kRuleCount; ++m) {
    const std::vector<double> means(r.mean_error.begin() + m * S, r.mean_error.begin() + (m + 1) * S);
    const OrderEstimate fit = estimate_order(r.steps, means);
    const bool ok = order_matches(fit, kRules[m].expected, opt.order_tolerance);  // false for NaN
    std::vector<Table::Cell> row{std::string(segment_rule_name(kRules[m].rule))};
    for (double e : means) row.emplace_back(e);
    row.emplace_back(kRules[m].expected);
    row.emplace_back(fit.order);
    row.emplace_back(std::string(ok ? "yes" : "NO"));
    t.add_row(std::move(row));
  }
  return t;
}

void run_demo(const DemoOptions& opt) {
  check(opt);
  const Scene scene = load_scene_or_default(opt.scene, memory_limit_bytes(opt.max_memory_gib));
  require_unshaded(scene, opt.scene.empty() ? "the default scene" : opt.scene, "vrv demo");
  require_grey(scene, opt.scene, "vrv demo");
  require_emission_absorption(opt.scene, "vrv demo");
  const DemoRun r = run(scene, opt);
  fmt::print("vrv demo: {} rays (fixed seed) through {}.\n\n", opt.rays,
             opt.scene.empty() ? "the embedded default scene (default_scene_toml, lib/scene_file.cpp)" : opt.scene);
  fmt::print("Mean |discrete - reference| per segment rule and step h (inviwo sampling), and the\n"
             "observed order (least-squares slope of log error against log h) against the expected:\n\n");
  fmt::print("{}\n", error_table(r, opt).to_markdown());
  long evaluations = 0, most = 0;
  double worst_estimate = 0;
  for (const ReferenceResult& ref : r.reference) {
    evaluations += ref.evaluations;
    most = std::max(most, ref.evaluations);
    worst_estimate = std::max(worst_estimate, ref.error_estimate);
  }
  const std::size_t finest = r.steps.size() - 1;
  fmt::print("The reference at tol {:.0e}: {:.1f} field evaluations per ray (at most {}), error estimate\n"
             "at most {:.2e} on every ray; the rules at h={:g} take {:.1f} samples per ray.\n\n",
             opt.tol, static_cast<double>(evaluations) / static_cast<double>(r.reference.size()), most,
             worst_estimate, r.steps[finest], r.samples_per_ray[finest]);
  fmt::print("Next: one ray, `vrv ray --help`; images, `vrv render --help`; the full studies with their\n"
             "tables, images and plots, `vrv study --list` and `vrv study NAME` (studies/NAME/, results\n"
             "in results/NAME/). Docs: README.md, docs/architecture.md, docs/studies.md.\n");
}

}  // namespace

void add_demo_command(CLI::App& app) {
  auto opt = std::make_shared<DemoOptions>();
  CLI::App* cmd = app.add_subcommand(
      "demo", "Start here: every segment rule's error and order against the reference, in seconds");
  cmd->add_option("--scene", opt->scene, "Scene file (TOML); the embedded default when omitted");
  add_volume_memory_option(*cmd, opt->max_memory_gib);
  cmd->add_option("--rays", opt->rays, "Number of rays")->capture_default_str();
  add_shared_option(*cmd, Option::tol, opt->tol);
  cmd->add_option("--step", opt->step, "Coarsest step (world units)")->capture_default_str();
  cmd->add_option("--halvings", opt->halvings, "Number of times the step is halved")->capture_default_str();
  cmd->callback([opt] { run_demo(*opt); });
}

}  // namespace vrv::cli
