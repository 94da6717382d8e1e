#include "studies/convergence/convergence.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <type_traits>
#include <variant>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "lib/io/atomic_file.h"
#include "lib/scene_file.h"
#include "lib/io/error_line.h"
#include "lib/io/table.h"
#include "lib/metrics.h"
#include "lib/reference_integrator.h"
#include "lib/util/parallel.h"
#include "lib/util/progress.h"
#include "lib/work_estimate.h"
#include "studies/engine/study_rays.h"
#include "studies/engine/reference_audit.h"

namespace vrv {
namespace {

constexpr long kMaxRays = 1'000'000;
constexpr std::size_t kMaxSteps = 64;
constexpr double kMaxSamplesPerRay = 1e8;  // per method and ray, as for every study method (study_file)

std::vector<int> read_resolutions(const StudyReader& r, const toml::table& t, std::string_view key) {
  const std::string at = StudyReader::child("grid_refinement", key);
  const std::vector<long> v = r.whole_numbers(t, key, "grid_refinement", 2, 513);
  r.check_distinct(v, "grid_refinement", key);
  // Every grid order is gated, and a gate's tolerance comes from the fit's spread (order_check).
  if (v.size() < 3) r.fail(at, "at least three resolutions (an order and its spread)");
  return std::vector<int>(v.begin(), v.end());
}

void read_grid_refinement(const StudyReader& r, const toml::table& doc, StudyDefinition& s) {
  const toml::table& g = r.table(*doc.get("grid_refinement"), "grid_refinement");
  r.check_keys(g, "grid_refinement", {"resolutions", "quick_resolutions", "expected_order", "steps_per_cell"});
  if (std::holds_alternative<GridField>(s.scene.field))
    r.fail("grid_refinement", "needs an analytic field in [scene.field] (it builds the grids itself)");
  s.grid_resolutions = read_resolutions(r, g, "resolutions");
  s.quick_grid_resolutions =
      g.contains("quick_resolutions") ? read_resolutions(r, g, "quick_resolutions") : s.grid_resolutions;
  s.grid_expected_order = r.number_or(g, "expected_order", "grid_refinement", 2);
  if (!(s.grid_expected_order > 0))
    r.fail("grid_refinement.expected_order", fmt::format("must be positive, got {}", s.grid_expected_order));
  s.grid_steps_per_cell = r.number_or(g, "steps_per_cell", "grid_refinement", 0.5);
  if (!(s.grid_steps_per_cell >= 0.01 && s.grid_steps_per_cell <= 10))
    r.fail("grid_refinement.steps_per_cell", fmt::format("must be in [0.01, 10], got {}", s.grid_steps_per_cell));
}

}  // namespace

StudyDefinition read_convergence_study(const StudyInput& in) {
  const StudyReader& r = in.reader;
  const toml::table& doc = in.doc;
  r.check_keys(doc, "", {"name", "kind", "description", "order_tolerance", "scene", "method", "sampling",
                         "rays", "reference_tol", "grid_refinement"});
  StudyDefinition s;
  s.source = r.source();
  s.name = in.name;
  if (doc.contains("description")) s.description = r.string(*doc.get("description"), "description");
  if (doc.contains("order_tolerance")) s.order_tolerance = read_order_tolerance(r, doc, "");
  s.reference_tol = read_reference_tol(r, doc, "", s.reference_tol);

  // [scene]: the usual scene tables, parsed by parse_scene; its keys reported as scene.<key>.
  s.scene = read_study_scene(r, doc, "", s.scene_toml);

  // [[method]]: rule and expected_order.
  const toml::node& methods = r.require(doc, "method", "");
  const toml::array* arr = methods.as_array();
  if (!arr) r.fail("method", "expected an array of tables ([[method]])");
  if (arr->empty()) r.fail("method", "no methods");
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const std::string path = fmt::format("method[{}]", i);
    const toml::table& m = r.table(*arr->get(i), path);
    r.check_keys(m, path, {"rule", "expected_order"});
    const SegmentRule rule = read_choice(r, r.require(m, "rule", path), path + ".rule", all_segment_rules(),
                                         parse_segment_rule, segment_rule_name);
    for (const StudyMethod& earlier : s.methods)
      if (earlier.rule == rule)
        r.fail(path + ".rule", fmt::format("'{}' is listed twice", segment_rule_name(rule)));
    s.methods.push_back({rule, r.positive(r.require(m, "expected_order", path), path + ".expected_order")});
  }

  // [sampling]: strategy and steps.
  const toml::table& sampling = r.table(r.require(doc, "sampling", ""), "sampling");
  r.check_keys(sampling, "sampling", {"strategy", "steps"});
  constexpr Strategy kStrategies[] = {Strategy::step, Strategy::inviwo};
  s.strategy = read_choice<Strategy>(r, r.require(sampling, "strategy", "sampling"), "sampling.strategy", kStrategies,
                                     parse_strategy, strategy_name);
  const toml::node& steps = r.require(sampling, "steps", "sampling");
  const toml::array* sa = steps.as_array();
  if (!sa) r.fail("sampling.steps", "expected an array of numbers");
  if (sa->size() > kMaxSteps) r.fail("sampling.steps", fmt::format("more than {} steps", kMaxSteps));
  for (std::size_t i = 0; i < sa->size(); ++i) {
    const std::string path = fmt::format("sampling.steps[{}]", i);
    const double h = r.positive(*sa->get(i), path);
    // Here, not at run time (where it would be reported as --step): a cap on the work per ray.
    const double samples = s.scene.box.extent().norm() / h;
    if (samples > kMaxSamplesPerRay)
      r.fail(path, fmt::format("step {:g} takes about {:.3g} samples per ray (at most {:g})", h, samples,
                               kMaxSamplesPerRay));
    if (std::find(s.steps.begin(), s.steps.end(), h) != s.steps.end())
      r.fail(path, fmt::format("step {} is listed twice", h));
    s.steps.push_back(h);
  }
  // Every method's order is gated, and a gate's tolerance comes from the fit's spread (order_check).
  if (s.steps.size() < 3) r.fail("sampling.steps", "at least three steps (an order and its spread)");

  if (doc.contains("grid_refinement")) read_grid_refinement(r, doc, s);

  // [rays]: count, quick_count, seed.
  const toml::table& rays = r.table(r.require(doc, "rays", ""), "rays");
  r.check_keys(rays, "rays", {"count", "quick_count", "seed"});
  s.count = r.integer(r.require(rays, "count", "rays"), "rays.count", 1, kMaxRays);
  s.quick_count = rays.contains("quick_count")
                      ? r.integer(*rays.get("quick_count"), "rays.quick_count", 1, kMaxRays)
                      : std::min(s.count, 8L);
  if (rays.contains("seed"))
    s.seed = static_cast<std::uint64_t>(
        r.integer(*rays.get("seed"), "rays.seed", 0, std::numeric_limits<long>::max()));
  return s;
}

StudyDefinition parse_study(std::string_view text, std::string_view source_name,
                             std::string_view default_name) {
  return read_grey_study(text, source_name, default_name, read_convergence_study);
}

StudyDefinition load_study(const std::filesystem::path& path) {
  return parse_study(read_study_text(path), path.string(), path.stem().string());
}

namespace {

// One method at world step h on the study's scene.
DiscreteConfig step_config(const StudyDefinition& study, SegmentRule rule, double h) {
  DiscreteConfig c;
  c.rule = rule;
  c.sampling.strategy = study.strategy;
  c.sampling.step = h;
  c.sampling.dims = study.scene.dims;
  return c;
}

// One method on the node grid of `resolution`^3, its step tied to the cell.
DiscreteConfig grid_config(const StudyDefinition& study, SegmentRule rule, int resolution) {
  DiscreteConfig c;
  c.rule = rule;
  c.sampling.strategy = study.strategy;
  c.sampling.step = study.grid_steps_per_cell * study.scene.box.extent().maxCoeff() / (resolution - 1);
  return c;
}

// The errors [method][ray] of "reference" and each rule on one node grid of `resolution`^3.
std::vector<double> grid_errors(const StudyDefinition& study, const AnalyticField& source,
                                const std::vector<Ray>& rays, const std::vector<double>& truth,
                                int resolution, Progress& bar) {
  const std::size_t n = rays.size(), M = study.methods.size() + 1;
  std::vector<double> error(M * n);
  const GridField grid = make_grid(study.scene.box, source, {resolution, resolution, resolution},
                                   GridLayout::node, Interpolation::trilinear);
  std::vector<DiscreteRaycaster<GridField>> casters;
  for (const StudyMethod& m : study.methods)
    casters.emplace_back(grid, study.scene.box, study.scene.transfer, study.scene.background,
                         grid_config(study, m.rule, resolution));
  parallel_for_index(static_cast<long>(n), [&](long i) {
    const Ray& ray = rays[static_cast<std::size_t>(i)];
    const double t = truth[static_cast<std::size_t>(i)];
    double* e = &error[static_cast<std::size_t>(i)];
    e[0] = std::abs(integrate_reference(grid, study.scene.box, study.scene.transfer,
                                        study.scene.background, ray, {study.reference_tol}).value - t);
    for (std::size_t m = 1; m < M; ++m) e[m * n] = std::abs(casters[m - 1].cast(ray).value - t);
    bar.advance();
  });
  return error;
}

// Error of each method on node grids of increasing resolution against the analytic reference:
// "reference" is the continuous integral through the trilinear grid (the reconstruction error
// alone); each rule runs at steps_per_cell x cell, so its error mixes both discretisations and
// its expected order is the smaller of the two.
void refine_grid(const StudyDefinition& study, bool quick, const std::vector<Ray>& rays, ReferenceAudit& audit,
                 bool progress, const StudyCheckpoint& checkpoint, StudyResult& result) {
  const std::vector<int>& res = quick ? study.quick_grid_resolutions : study.grid_resolutions;
  const auto& source = std::visit(
      [](const auto& f) -> AnalyticField {
        if constexpr (std::is_same_v<std::decay_t<decltype(f)>, GridField>) throw std::logic_error("grid");
        else return f;
      },
      study.scene.field);
  const std::size_t n = rays.size(), M = study.methods.size() + 1, R = res.size();
  const std::vector<double> truth = checkpointed(checkpoint, "grid_truth", n, [&] {
    std::vector<double> t(n);
    parallel_for_index(static_cast<long>(n), [&](long i) {
      t[static_cast<std::size_t>(i)] =
          audited_reference(audit, study.scene, rays[static_cast<std::size_t>(i)], {study.reference_tol}).value;
    });
    return t;
  });
  std::vector<double> error(R * M * n);  // [resolution][method][ray]
  Progress bar("study " + study.name + " (grids)", static_cast<long>(R * n), progress);
  for (std::size_t k = 0; k < R; ++k) {
    // One resolution is one checkpoint: its M x n errors.
    const std::vector<double> errors_k = checkpointed(checkpoint, fmt::format("grid_{}", res[k]), M * n, [&] {
      return grid_errors(study, source, rays, truth, res[k], bar);
    });
    std::copy(errors_k.begin(), errors_k.end(), error.begin() + static_cast<std::ptrdiff_t>(k * M * n));
  }
  bar.finish();
  for (std::size_t m = 0; m < M; ++m) {
    const std::string name = m == 0 ? "reference" : std::string(segment_rule_name(study.methods[m - 1].rule));
    std::vector<double> cells, means;
    for (std::size_t k = 0; k < R; ++k) {
      GridErrorRow row{name, res[k], study.scene.box.extent().maxCoeff() / (res[k] - 1), 0, 0};
      for (std::size_t i = 0; i < n; ++i) {
        const double e = error[(k * M + m) * n + i];
        row.max_error = std::max(row.max_error, e);
        row.mean_error += e / static_cast<double>(n);
      }
      cells.push_back(row.cell);
      means.push_back(row.mean_error);
      result.grid_errors.push_back(row);
    }
    const double expected = m == 0 ? study.grid_expected_order
                                   : std::min(study.grid_expected_order, study.methods[m - 1].expected_order);
    const OrderEstimate fit = estimate_order(cells, means);
    GridOrderRow o{name, expected, fit.order, order_matches(fit, expected, study.order_tolerance), fit};
    result.pass = result.pass && o.pass;
    result.grid_orders.push_back(o);
  }
}

}  // namespace

StudyResult run_convergence(const StudyDefinition& study, bool quick, ReferenceAudit& audit, bool progress,
                            const StudyCheckpoint& checkpoint) {
  const long n = quick ? study.quick_count : study.count;
  const std::vector<Ray> rays = study_rays(study.scene.box, n, study.seed);
  const std::size_t M = study.methods.size(), S = study.steps.size();
  const std::size_t per_ray = M * S;
  std::vector<double> error(static_cast<std::size_t>(n) * per_ray);
  std::vector<long> samples(error.size());

  visit_field(study.scene, [&](const auto& field) {
    using F = std::decay_t<decltype(field)>;
    std::vector<DiscreteRaycaster<F>> casters;
    casters.reserve(per_ray);
    for (const StudyMethod& m : study.methods)
      for (double h : study.steps) {
        const DiscreteConfig c = step_config(study, m.rule, h);
        validate(c, std::is_same_v<F, GridField>);
        casters.emplace_back(field, study.scene.box, study.scene.transfer, study.scene.background, c);
      }
    Progress bar("study " + study.name, n, progress);
    parallel_for_index(n, [&](long i) {
      // One ray is one checkpoint: its errors, then its sample counts (exact as doubles).
      const std::vector<double> v = checkpointed(checkpoint, fmt::format("ray_{}", i), 2 * per_ray, [&] {
        const Ray& ray = rays[static_cast<std::size_t>(i)];
        const double reference = audited_reference(audit, field, study.scene.box, study.scene.transfer,
                                                   study.scene.background, ray,
                                                   {study.reference_tol}).value;
        std::vector<double> out(2 * per_ray);
        for (std::size_t k = 0; k < per_ray; ++k) {
          const DiscreteResult d = casters[k].cast(ray);
          out[k] = std::abs(d.value - reference);
          out[per_ray + k] = static_cast<double>(d.samples);
        }
        return out;
      });
      for (std::size_t k = 0; k < per_ray; ++k) {
        error[static_cast<std::size_t>(i) * per_ray + k] = v[k];
        samples[static_cast<std::size_t>(i) * per_ray + k] = static_cast<long>(v[per_ray + k]);
      }
      bar.advance();
    });
    bar.finish();
  });

  // Reductions in ray order: the same bits for any thread count.
  StudyResult result;
  result.rays = n;
  for (std::size_t m = 0; m < M; ++m) {
    std::vector<double> means;
    for (std::size_t s = 0; s < S; ++s) {
      const std::size_t k = m * S + s;
      double max_e = 0, sum_e = 0, sum_samples = 0;
      for (long i = 0; i < n; ++i) {
        const double e = error[static_cast<std::size_t>(i) * per_ray + k];
        max_e = std::max(max_e, e);
        sum_e += e;
        sum_samples += static_cast<double>(samples[static_cast<std::size_t>(i) * per_ray + k]);
      }
      const double nd = static_cast<double>(n);
      result.errors.push_back({study.methods[m].rule, study.steps[s], max_e, sum_e / nd, sum_samples / nd});
      means.push_back(sum_e / nd);
    }
    const OrderEstimate fit = estimate_order(study.steps, means);
    const double expected = study.methods[m].expected_order;
    OrderRow o{study.methods[m].rule, expected, fit.order, order_matches(fit, expected, study.order_tolerance), fit};
    result.pass = result.pass && o.pass;
    result.orders.push_back(o);
  }
  if (!study.grid_resolutions.empty()) refine_grid(study, quick, rays, audit, progress, checkpoint, result);
  return result;
}

StudyWork convergence_work(const StudyDefinition& study, bool quick) {
  const double n = static_cast<double>(quick ? study.quick_count : study.count);
  StudyWork work;
  work.add("reference truths", n, reference_evaluations(study.scene, study.reference_tol));
  for (const StudyMethod& m : study.methods)
    for (double h : study.steps)
      work.add(fmt::format("{} at step {:g}", segment_rule_name(m.rule), h), n,
               discrete_samples(step_config(study, m.rule, h), study.scene));
  const std::vector<int>& resolutions = quick ? study.quick_grid_resolutions : study.grid_resolutions;
  if (!resolutions.empty()) work.add("grid truths", n, reference_evaluations(study.scene, study.reference_tol));
  for (int res : resolutions) {
    work.add(fmt::format("grid {}^3 built", res), 1, std::pow(double(res), 3));  // the analytic field at every node
    double per_ray = grid_reference_evaluations({res, res, res}, 3);
    for (const StudyMethod& m : study.methods) per_ray += discrete_samples(grid_config(study, m.rule, res), study.scene);
    work.add(fmt::format("grid {}^3", res), n, per_ray);
  }
  return work;
}

StudyFiles study_tables(const StudyDefinition& study, const StudyResult& result) {
  Table errors({"method", "step", "max_error", "mean_error", "samples_per_ray"});
  errors.set_format("max_error", "{:.3e}");
  errors.set_format("mean_error", "{:.3e}");
  for (const ErrorRow& e : result.errors)
    errors.add_row({std::string(segment_rule_name(e.rule)), e.step, e.max_error, e.mean_error,
                    e.samples_per_ray});
  Table orders({"method", "expected", "observed", "pass"});
  orders.allow_missing("observed");
  orders.set_format("expected", "{:g}");
  orders.set_format("observed", "{:.3f}");
  for (const OrderRow& o : result.orders)
    orders.add_row({std::string(segment_rule_name(o.rule)), o.expected, o.observed,
                    std::string(o.pass ? "true" : "false")});
  LatexStyle style;
  style.caption = fmt::format("Observed convergence orders ({} rays, tolerance max({:g} c SE, {:g})).",
                              result.rays, study.order_tolerance.margin, study.order_tolerance.floor);
  style.label = "tab:" + study.name;
  StudyFiles files;
  files.errors_csv = errors.to_csv();
  files.orders_csv = orders.to_csv();
  files.orders_md = orders.to_markdown();
  files.orders_tex = orders.to_latex(style);
  if (result.grid_errors.empty()) return files;
  Table grid_errors({"method", "resolution", "cell", "max_error", "mean_error"});
  grid_errors.set_format("max_error", "{:.3e}");
  grid_errors.set_format("mean_error", "{:.3e}");
  for (const GridErrorRow& e : result.grid_errors)
    grid_errors.add_row({e.method, static_cast<long>(e.resolution), e.cell, e.max_error, e.mean_error});
  Table grid_orders({"method", "expected", "observed", "pass"});
  grid_orders.allow_missing("observed");
  grid_orders.set_format("expected", "{:g}");
  grid_orders.set_format("observed", "{:.3f}");
  for (const GridOrderRow& o : result.grid_orders)
    grid_orders.add_row({o.method, o.expected, o.observed, std::string(o.pass ? "true" : "false")});
  LatexStyle grid_style;
  grid_style.caption = fmt::format(
      "Observed orders under grid refinement (node grids, trilinear; discrete step {:g} cells; "
      "{} rays, tolerance max({:g} c SE, {:g})).", study.grid_steps_per_cell, result.rays,
      study.order_tolerance.margin, study.order_tolerance.floor);
  grid_style.label = "tab:" + study.name + "-grid";
  files.grid_errors_csv = grid_errors.to_csv();
  files.grid_orders_csv = grid_orders.to_csv();
  files.grid_orders_md = grid_orders.to_markdown();
  files.grid_orders_tex = grid_orders.to_latex(grid_style);
  return files;
}

nlohmann::json study_parameters(const StudyDefinition& study, bool quick, int threads) {
  nlohmann::ordered_json p;
  p["study"] = study.name;
  p["file"] = study.source;
  p["kind"] = "convergence";
  p["description"] = study.description;
  p["scene"] = study.scene_toml;
  nlohmann::ordered_json methods = nlohmann::ordered_json::array();
  for (const StudyMethod& m : study.methods)
    methods.push_back({{"rule", std::string(segment_rule_name(m.rule))},
                       {"expected_order", m.expected_order}});
  p["methods"] = methods;
  p["strategy"] = std::string(strategy_name(study.strategy));
  p["steps"] = study.steps;
  p["rays"] = {{"count", study.count}, {"quick_count", study.quick_count}, {"seed", study.seed},
               {"used", quick ? study.quick_count : study.count}};
  p["order_tolerance"] = {{"margin", study.order_tolerance.margin}, {"floor", study.order_tolerance.floor}};
  p["reference_tol"] = study.reference_tol;
  if (!study.grid_resolutions.empty())
    p["grid_refinement"] = {{"resolutions", study.grid_resolutions},
                            {"quick_resolutions", study.quick_grid_resolutions},
                            {"expected_order", study.grid_expected_order},
                            {"steps_per_cell", study.grid_steps_per_cell}};
  p["quick"] = quick;
  p["threads"] = threads;  // recorded only; no number depends on it
  return nlohmann::json::parse(p.dump());
}

void write_study_tables(const std::filesystem::path& dir, const StudyDefinition& study,
                        const StudyResult& result) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir))
    throw std::runtime_error(one_line(fmt::format("{}: cannot create the directory{}", dir.string(),
                                                  ec ? ": " + ec.message() : std::string())));
  const StudyFiles f = study_tables(study, result);
  write_file_atomically(dir / "errors.csv", f.errors_csv);
  write_file_atomically(dir / "orders.csv", f.orders_csv);
  write_file_atomically(dir / "orders.md", f.orders_md);
  write_file_atomically(dir / "orders.tex", f.orders_tex);
  if (f.grid_errors_csv.empty()) return;
  write_file_atomically(dir / "grid_errors.csv", f.grid_errors_csv);
  write_file_atomically(dir / "grid_orders.csv", f.grid_orders_csv);
  write_file_atomically(dir / "grid_orders.md", f.grid_orders_md);
  write_file_atomically(dir / "grid_orders.tex", f.grid_orders_tex);
}

}  // namespace vrv
