#include "studies/projections/projections.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "lib/io/atomic_file.h"
#include "lib/io/table.h"
#include "lib/projection/projection_reference.h"
#include "lib/study_file.h"
#include "lib/util/parallel.h"
#include "lib/work_estimate.h"
#include "studies/engine/study_rays.h"

namespace vrv {
namespace {

ProjectionsMethod read_method(const StudyReader& r, const toml::table& m, const std::string& path) {
  r.check_keys(m, path, {"mode", "method", "strategy", "expected_order", "maxima"});
  ProjectionsMethod out;
  const std::string mode = r.string(r.require(m, "mode", path), path + ".mode");
  const auto parsed = parse_projection_mode(mode);
  if (!parsed) r.fail(path + ".mode", fmt::format("unknown mode '{}' (one of {})", mode, projection_mode_list()));
  out.config.mode = *parsed;
  const std::string method = r.string(r.require(m, "method", path), path + ".method");
  if (is_mip(*parsed)) {
    if (method != "max") r.fail(path + ".method", fmt::format("unknown method '{}' for mode {} (max)", method, mode));
  } else {
    const auto rule = parse_xray_rule(method);
    if (!rule) r.fail(path + ".method", fmt::format("unknown method '{}' for mode {} ({})", method, mode, xray_rule_list()));
    out.config.rule = *rule;
  }
  const std::string strategy = r.string(r.require(m, "strategy", path), path + ".strategy");
  const auto st = parse_strategy(strategy);
  if (!st || !step_based(*st))
    r.fail(path + ".strategy", fmt::format("'{}' is not a step-based strategy ({})", strategy, strategy_list(strategies_where(step_based))));
  out.config.sampling.strategy = *st;
  out.expected_order = r.number(r.require(m, "expected_order", path), path + ".expected_order");
  if (!(out.expected_order > 0)) r.fail(path + ".expected_order", "must be positive");
  if (m.contains("maxima")) {
    out.maxima = r.string(*m.get("maxima"), path + ".maxima");
    const std::vector<std::string> classes{"interior", "face", "entry", "exit", "all"};
    if (std::find(classes.begin(), classes.end(), out.maxima) == classes.end())
      r.fail(path + ".maxima", fmt::format("unknown value '{}' (interior, face, entry, exit or all)", out.maxima));
    if (!is_mip(*parsed) && out.maxima != "all") r.fail(path + ".maxima", "applies to the MIP modes only");
  }
  out.label = fmt::format("{} {} {}{}", mode, method, strategy, out.maxima == "all" ? "" : " (" + out.maxima + " maxima)");
  return out;
}

}  // namespace

ProjectionsStudy read_projections_study(const StudyInput& in) {
  const StudyReader& r = in.reader;
  const toml::table& doc = in.doc;
  r.check_keys(doc, "", {"name", "kind", "description", "order_tolerance", "reference_tol", "rays", "quick_rays",
                         "seed", "steps", "scene", "method", "image_size", "quick_image_size"});
  ProjectionsStudy s;
  s.name = in.name;
  if (doc.contains("description")) s.description = r.string(*doc.get("description"), "description");
  if (doc.contains("order_tolerance")) s.order_tolerance = read_order_tolerance(r, doc, "");
  const RaySample sample = read_ray_sample(r, doc, {s.rays, s.quick_rays, s.seed, s.reference_tol});
  s.rays = sample.rays, s.quick_rays = sample.quick_rays, s.seed = sample.seed, s.reference_tol = sample.reference_tol;
  s.image_size = static_cast<int>(r.integer_or(doc, "image_size", "", 1, 4096, s.image_size));
  s.quick_image_size = static_cast<int>(r.integer_or(doc, "quick_image_size", "", 1, 4096, s.quick_image_size));
  s.steps = read_refinement_steps(r, doc);
  std::string scene_toml;
  s.scene = read_study_scene(r, doc, "", scene_toml);
  // X-ray and MIP see the extinction and the field, which an RGB scene's channels share: a study
  // per channel would be one study three times.
  if (r.saw_rgb_scene())
    r.fail("scene", "the scene is RGB (three-valued points), and a projection has one channel: give it a grey scene");
  const toml::node& methods = r.require(doc, "method", "");
  const toml::array* arr = methods.as_array();
  if (!arr || arr->empty()) r.fail("method", "expected a non-empty array of tables ([[method]])");
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const std::string path = fmt::format("method[{}]", i);
    s.methods.push_back(read_method(r, r.table(*arr->get(i), path), path));
    s.methods.back().config.sampling.dims = s.scene.dims;
  }
  return s;
}

ProjectionsResult run_projections(const ProjectionsStudy& study, bool quick) {
  ProjectionsResult out;
  out.rays = quick ? study.quick_rays : study.rays;
  const std::vector<Ray> rays = study_rays(study.scene.box, out.rays, study.seed);
  // The references, once per mode and ray.
  std::map<ProjectionMode, std::vector<ProjectionResult>> refs;
  for (const ProjectionsMethod& m : study.methods) refs[m.config.mode];
  for (auto& [mode_key, values_of_mode] : refs) {
    // Named copies: clang 14 (the fuzz build) cannot capture structured bindings in a lambda.
    const ProjectionMode mode = mode_key;
    std::vector<ProjectionResult>& values = values_of_mode;
    values.resize(rays.size());
    parallel_for_index(out.rays, [&](long i) {
      values[i] = projection_reference(study.scene, rays[i], mode, {study.reference_tol});
    });
    for (const ProjectionResult& v : values) out.truths.add(v);
  }
  const double largest = *std::max_element(study.steps.begin(), study.steps.end());
  for (const ProjectionsMethod& m : study.methods) {
    // The rays of the method's class of maxima (by where the reference puts the maximum).
    std::vector<char> in(rays.size(), 1);
    long count = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const ProjectionResult& ref = refs.at(m.config.mode)[i];
      const double inside = std::min(ref.position - ref.t_entry, ref.t_exit - ref.position);
      if (m.maxima == "interior") in[i] = inside > 2 * largest;
      if (m.maxima == "face") in[i] = inside == 0;
      if (m.maxima == "entry") in[i] = ref.position == ref.t_entry;
      if (m.maxima == "exit") in[i] = ref.position == ref.t_exit && ref.position != ref.t_entry;
      count += in[i] && ref.hit;
    }
    std::vector<double> errors;
    for (double h : study.steps) {
      DiscreteProjectionConfig c = m.config;
      c.sampling.step = h;
      std::vector<double> e(rays.size());
      parallel_for_index(out.rays, [&](long i) {
        const ProjectionResult& ref = refs.at(m.config.mode)[i];
        e[i] = ref.hit && in[i] ? std::abs(discrete_projection(study.scene, rays[i], c).value - ref.value) : 0.0;
      });
      double sum = 0, worst = 0;
      for (double x : e) sum += x, worst = std::max(worst, x);
      const double mean = count > 0 ? sum / static_cast<double>(count) : 0.0;
      out.errors.push_back({m.label, count, h, mean, worst});
      errors.push_back(mean);
    }
    out.orders.push_back({m.label, m.expected_order, estimate_order(study.steps, errors)});
  }
  return out;
}

namespace {

constexpr const char* kPlots = R"json({
  "plots": [
    {"name": "convergence", "csv": "errors.csv", "style": "lines", "x": "step", "y": "mean_error",
     "group": "method", "xscale": "log", "yscale": "log", "fit": true,
     "xlabel": "step (world units)", "ylabel": "mean |discrete - reference|",
     "title": "Projections: error against step"}
  ]
}
)json";

}  // namespace

void write_projections(const std::filesystem::path& dir, const ProjectionsStudy& study, const ProjectionsResult& result) {
  Table errors({"method", "rays", "step", "mean_error", "max_error"});
  errors.set_format("mean_error", "{:.3e}");
  errors.set_format("max_error", "{:.3e}");
  for (const ProjectionsRow& r : result.errors) errors.add_row({r.method, r.rays, r.step, r.mean_error, r.max_error});
  Table orders({"method", "expected", "observed", "standard_error", "tolerance", "ok"});
  orders.allow_missing("standard_error");
  orders.allow_missing("tolerance");
  orders.allow_missing("observed");
  orders.set_format("observed", "{:.2f}");
  for (const ProjectionsOrder& o : result.orders) {
    const double tol = order_tolerance(o.fit, study.order_tolerance);
    orders.add_row({o.method, o.expected, o.fit.order, o.fit.standard_error, tol,
                    std::string(order_matches(o.fit, o.expected, study.order_tolerance) ? "yes" : "no")});
  }
  LatexStyle style;
  style.caption = "Projections: observed against expected orders under step refinement";
  style.label = "tab:projections";
  write_file_atomically(dir / "errors.csv", errors.to_csv());
  write_file_atomically(dir / "errors.md", errors.to_markdown());
  write_file_atomically(dir / "orders.csv", orders.to_csv());
  write_file_atomically(dir / "orders.md", orders.to_markdown());
  write_file_atomically(dir / "orders.tex", orders.to_latex(style));
  write_file_atomically(dir / "plots.json", kPlots);
}

std::vector<StudyCheck> projections_checks(const ProjectionsStudy& study, const ProjectionsResult& result) {
  std::vector<StudyCheck> checks;
  for (const ProjectionsOrder& o : result.orders)
    checks.push_back(order_check(fmt::format("order {}", o.method), o.fit, o.expected, study.order_tolerance));
  checks.push_back({"references within reference_tol", result.truths.largest_estimate, study.reference_tol,
                    result.truths.missed == 0,
                    fmt::format("largest error estimate of the X-ray and MIP references; {} missed",
                                result.truths.missed),
                    CheckKind::derived});
  return checks;
}

StudyWork projections_work(const ProjectionsStudy& study, bool quick) {
  StudyWork work;
  const double rays = static_cast<double>(quick ? study.quick_rays : study.rays);
  // MIP candidates and Brent's refinements add little to the panels the emission-absorption
  // reference would fit: its estimate stands for each mode's.
  std::vector<ProjectionMode> modes;
  for (const ProjectionsMethod& m : study.methods)
    if (std::find(modes.begin(), modes.end(), m.config.mode) == modes.end()) modes.push_back(m.config.mode);
  work.add("references", rays * static_cast<double>(modes.size()), reference_evaluations(study.scene, study.reference_tol));
  for (const ProjectionsMethod& m : study.methods)
    for (double h : study.steps) {
      DiscreteConfig c;
      c.sampling = m.config.sampling;
      c.sampling.step = h;
      // Simpson samples each segment's midpoint too.
      const double factor = m.config.rule == XrayRule::simpson && !is_mip(m.config.mode) ? 2 : 1;
      work.add(fmt::format("{} at step {:g}", m.label, h), rays, factor * discrete_samples(c, study.scene));
    }
  add_images_work(study, quick, work);
  return work;
}

}  // namespace vrv
