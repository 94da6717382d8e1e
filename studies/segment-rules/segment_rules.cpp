// Study kind "segment_rules": Moreland's average-opacity approximation of zeta and Psi against
// the exact values over front and back opacities of a unit segment (thesis Figs. 1.6, 1.7), and
// the image error and observed order of riemann, alpha, trapezoid, exact_linear and moreland.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "lib/io/atomic_file.h"
#include "lib/io/image_io.h"
#include "lib/io/table.h"
#include "studies/engine/checkpoint.h"
#include "studies/engine/study_driver.h"
#include "studies/engine/study_outputs.h"
#include "studies/segment-rules/segment_rules.h"

namespace vrv {
namespace {

struct UnitSpec {
  long points = 101, quick_points = 21;
  double alpha_top = 0;
  double identity_tolerance = 0, independent_tolerance = 0;
  // Stated bounds on max |average - exact|: zeta, Psi for linear alpha, then for linear tau.
  double max_error[2][2] = {{0, 0}, {0, 0}};
};

struct SegmentRulesStudy {
  UnitSpec unit;
  std::vector<RuleSpec> rules;
  Strategy strategy = Strategy::inviwo;
  double reference_tol = 1e-12;
  OrderTolerance order_tolerance;
  std::vector<RenderSpec> renders;
};

constexpr const char* kModels[2] = {"linear_alpha", "linear_tau"};
constexpr const char* kQuantities[2] = {"zeta", "psi"};

// ---- Reading the file ----

UnitSpec read_unit(const StudyReader& r, const toml::table& doc) {
  const std::string at = "unit_segment";
  const toml::table& t = r.table(r.require(doc, "unit_segment", ""), at);
  r.check_keys(t, at, {"points", "quick_points", "alpha_top", "identity_tolerance",
                       "independent_tolerance", "max_error"});
  UnitSpec u;
  u.points = r.integer(r.require(t, "points", at), at + ".points", 2, 2001);
  u.quick_points = r.integer(r.require(t, "quick_points", at), at + ".quick_points", 2, 2001);
  u.alpha_top = r.number(r.require(t, "alpha_top", at), at + ".alpha_top");
  if (!(u.alpha_top > 0 && u.alpha_top < 1)) r.fail(at + ".alpha_top", "must be in (0, 1)");
  u.identity_tolerance = r.non_negative(r.require(t, "identity_tolerance", at), at + ".identity_tolerance");
  u.independent_tolerance =
      r.non_negative(r.require(t, "independent_tolerance", at), at + ".independent_tolerance");
  const std::string mat = at + ".max_error";
  const toml::table& m = r.table(r.require(t, "max_error", at), mat);
  r.check_keys(m, mat, {"zeta_linear_alpha", "psi_linear_alpha", "zeta_linear_tau", "psi_linear_tau"});
  for (int model = 0; model < 2; ++model)
    for (int q = 0; q < 2; ++q) {
      const std::string key = fmt::format("{}_{}", kQuantities[q], kModels[model]);
      u.max_error[model][q] = r.non_negative(r.require(m, key, mat), StudyReader::child(mat, key));
    }
  return u;
}

}  // namespace

std::vector<RuleSpec> read_rules(const StudyReader& r, const toml::table& images) {
  std::vector<RuleSpec> rules;
  const toml::array& arr = r.array(r.require(images, "rule", "images"), "images.rule");
  for (std::size_t i = 0; i < arr.size(); ++i) {
    const std::string at = fmt::format("images.rule[{}]", i);
    const toml::table& t = r.table(arr[i], at);
    r.check_keys(t, at, {"rule", "expected_order"});
    const SegmentRule rule = read_choice(r, r.require(t, "rule", at), at + ".rule", all_segment_rules(),
                                         parse_segment_rule, segment_rule_name);
    for (const RuleSpec& earlier : rules)
      if (earlier.rule == rule) r.fail(at + ".rule", fmt::format("'{}' is listed twice", segment_rule_name(rule)));
    rules.push_back({rule, r.positive(r.require(t, "expected_order", at), at + ".expected_order")});
  }
  if (rules.empty()) r.fail("images.rule", "needs at least one rule");
  return rules;
}

RenderSpec read_render(const StudyReader& r, const toml::table& t, const std::string& at) {
  r.check_keys(t, at, {"name", "description", "steps", "quick_steps", "map_step", "quick_width",
                       "quick_height", "check_orders", "scene"});
  RenderSpec s;
  s.name = r.string(r.require(t, "name", at), at + ".name");
  if (s.name.empty() || s.name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789-_") != std::string::npos)
    r.fail(at + ".name", "must be non-empty, lower-case letters, digits, '-' or '_' (it names files)");
  if (const toml::node* d = t.get("description")) s.description = r.string(*d, at + ".description");
  s.scene = read_study_scene(r, t, at, s.scene_toml);
  if (!s.scene.camera) r.fail(at + ".scene.camera", "a render needs a camera");
  if (s.scene.camera->projection == Projection::fan) r.fail(at + ".scene.camera", "needs an image camera, not a fan");
  s.steps = r.numbers(t, "steps", at, 1e-6, 10);
  s.quick_steps = r.numbers(t, "quick_steps", at, 1e-6, 10);
  r.check_distinct(s.steps, at, "steps");
  r.check_distinct(s.quick_steps, at, "quick_steps");
  if (const toml::node* c = t.get("check_orders")) s.check_orders = r.boolean(*c, at + ".check_orders");
  // A gated order's tolerance comes from the fit's spread (order_check): three steps at least.
  const std::size_t fewest = s.check_orders ? 3 : 2;
  const char* why = s.check_orders ? "at least three steps (a gated order and its spread)" : "at least two steps (an order)";
  if (s.steps.size() < fewest) r.fail(at + ".steps", why);
  if (s.quick_steps.size() < fewest) r.fail(at + ".quick_steps", why);
  s.map_step = r.number(r.require(t, "map_step", at), at + ".map_step");
  auto has = [&](const std::vector<double>& v) { return std::find(v.begin(), v.end(), s.map_step) != v.end(); };
  if (!has(s.steps) || !has(s.quick_steps)) r.fail(at + ".map_step", "must be one of steps and of quick_steps");
  s.quick_width = static_cast<int>(r.integer(r.require(t, "quick_width", at), at + ".quick_width", 1, 4096));
  s.quick_height = static_cast<int>(r.integer(r.require(t, "quick_height", at), at + ".quick_height", 1, 4096));
  return s;
}

ImageSettings read_images(const StudyReader& r, const toml::table& doc) {
  ImageSettings st;
  const toml::table& images = r.table(r.require(doc, "images", ""), "images");
  r.check_keys(images, "images", {"strategy", "reference_tol", "order_tolerance", "rule"});
  st.strategy = read_choice<Strategy>(r, r.require(images, "strategy", "images"), "images.strategy",
                                      strategies_where(step_based), parse_strategy, strategy_name);
  st.reference_tol = read_reference_tol(r, images, "images");
  st.order_tolerance = read_order_tolerance(r, images, "images");
  st.rules = read_rules(r, images);
  return st;
}

namespace {

SegmentRulesStudy read_study(const StudyInput& in) {
  const StudyReader& r = in.reader;
  r.check_keys(in.doc, "", {"kind", "name", "description", "unit_segment", "images", "render"});
  SegmentRulesStudy st;
  st.unit = read_unit(r, in.doc);
  ImageSettings images = read_images(r, in.doc);
  st.strategy = images.strategy;
  st.reference_tol = images.reference_tol;
  st.order_tolerance = images.order_tolerance;
  st.rules = std::move(images.rules);
  const toml::array& renders = r.array(r.require(in.doc, "render", ""), "render");
  if (renders.empty()) r.fail("render", "needs at least one [[render]]");
  for (std::size_t i = 0; i < renders.size(); ++i) {
    const std::string at = fmt::format("render[{}]", i);
    st.renders.push_back(read_render(r, r.table(renders[i], at), at));
    for (std::size_t k = 0; k + 1 < st.renders.size(); ++k)
      if (st.renders[k].name == st.renders.back().name)  // it names the images, which would be overwritten
        r.fail(at + ".name", fmt::format("'{}' is listed twice (render[{}] has it)", st.renders.back().name, k));
  }
  return st;
}

// ---- The unit segment ----

struct UnitCell {
  double alpha_f = 0, alpha_b = 0;
  ZetaPsi exact[2], average, quadrature[2];  // [model]
};

double value(const ZetaPsi& v, int q) { return q == 0 ? v.zeta : v.psi; }

// One row of the grid (one alpha_back) is one checkpoint: per cell, the five (zeta, Psi) pairs.
std::vector<UnitCell> run_unit(const UnitSpec& u, bool quick, Checkpoints* checkpoints) {
  const std::vector<double> alphas = opacity_grid(quick ? u.quick_points : u.points, u.alpha_top);
  const long n = static_cast<long>(alphas.size());
  constexpr std::size_t kWidth = 10;
  const std::vector<double> v = checkpointed_items(checkpoints, "unit", n * n, n, kWidth, [&](long i, std::span<double> o) {
    const double f = alphas[static_cast<std::size_t>(i % n)], b = alphas[static_cast<std::size_t>(i / n)];
    const ZetaPsi z[] = {linear_alpha_segment(f, b), linear_tau_segment(f, b), average_opacity_segment(f, b),
                         linear_alpha_by_quadrature(f, b), linear_tau_by_quadrature(f, b)};
    for (std::size_t k = 0; k < 5; ++k) o[2 * k] = z[k].zeta, o[2 * k + 1] = z[k].psi;
  });
  std::vector<UnitCell> cells(static_cast<std::size_t>(n * n));  // alpha_back outer, alpha_front inner
  for (std::size_t i = 0; i < cells.size(); ++i) {
    UnitCell& c = cells[i];
    const double* o = v.data() + i * kWidth;
    c.alpha_f = alphas[i % static_cast<std::size_t>(n)];
    c.alpha_b = alphas[i / static_cast<std::size_t>(n)];
    ZetaPsi* z[] = {&c.exact[0], &c.exact[1], &c.average, &c.quadrature[0], &c.quadrature[1]};
    for (std::size_t k = 0; k < 5; ++k) *z[k] = {o[2 * k], o[2 * k + 1]};
  }
  return cells;
}

struct UnitSummary {
  double max_error = 0, signed_error = 0, at_f = 0, at_b = 0, mean_error = 0;
  double diagonal = 0;     // max |average - exact| where alpha_f = alpha_b
  double independent = 0;  // max |exact - quadrature|
};

UnitSummary summarise(const std::vector<UnitCell>& cells, int model, int q) {
  UnitSummary s;
  for (const UnitCell& c : cells) {
    const double e = value(c.average, q) - value(c.exact[model], q);
    if (std::abs(e) > s.max_error) s = {std::abs(e), e, c.alpha_f, c.alpha_b, s.mean_error, s.diagonal, s.independent};
    s.mean_error += std::abs(e);
    if (c.alpha_f == c.alpha_b) s.diagonal = std::max(s.diagonal, std::abs(e));
    s.independent = std::max(s.independent, std::abs(value(c.exact[model], q) - value(c.quadrature[model], q)));
  }
  s.mean_error /= static_cast<double>(cells.size());
  return s;
}

long non_finite(const std::vector<UnitCell>& cells) {
  long count = 0;
  for (const UnitCell& c : cells)
    for (double v : {c.exact[0].zeta, c.exact[0].psi, c.exact[1].zeta, c.exact[1].psi, c.average.zeta,
                     c.average.psi, c.quadrature[0].zeta, c.quadrature[0].psi, c.quadrature[1].zeta,
                     c.quadrature[1].psi})
      count += !std::isfinite(v);
  return count;
}

Table unit_table(const std::vector<UnitCell>& cells) {
  Table t({"alpha_front", "alpha_back", "zeta_linear_alpha", "psi_linear_alpha", "zeta_linear_tau",
           "psi_linear_tau", "zeta_average", "psi_average", "zeta_error", "psi_error",
           "zeta_error_linear_tau", "psi_error_linear_tau"});
  for (const UnitCell& c : cells)
    t.add_row({c.alpha_f, c.alpha_b, c.exact[0].zeta, c.exact[0].psi, c.exact[1].zeta, c.exact[1].psi,
               c.average.zeta, c.average.psi, c.average.zeta - c.exact[0].zeta, c.average.psi - c.exact[0].psi,
               c.average.zeta - c.exact[1].zeta, c.average.psi - c.exact[1].psi});
  return t;
}

// The error of the approximation as an image: x = alpha_front, y = alpha_back (top row = largest).
Image unit_error_image(const std::vector<UnitCell>& cells, int model, int q) {
  const int n = static_cast<int>(std::lround(std::sqrt(static_cast<double>(cells.size()))));
  Image img(n, n);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const UnitCell& c = cells[static_cast<std::size_t>((n - 1 - y) * n + x)];
      img.at(x, y) = static_cast<float>(value(c.average, q) - value(c.exact[model], q));
    }
  return img;
}

// ---- Outputs ----

constexpr const char* kUnitPlots[][4] = {
    // name, z, zlabel, title
    {"zeta_linear_alpha", "zeta_linear_alpha", "zeta", "Fig. 1.6(a): zeta, linearly interpolated opacity"},
    {"zeta_average", "zeta_average", "zeta", "Fig. 1.6(b): zeta, average opacity"},
    {"zeta_error", "zeta_error", "average - exact", "zeta: average opacity - linear opacity"},
    {"psi_linear_alpha", "psi_linear_alpha", "Psi", "Fig. 1.7(a): Psi, linearly interpolated opacity"},
    {"psi_average", "psi_average", "Psi", "Fig. 1.7(b): Psi, average opacity"},
    {"psi_error", "psi_error", "average - exact", "Psi: average opacity - linear opacity"},
    {"zeta_error_linear_tau", "zeta_error_linear_tau", "average - exact", "zeta: average opacity - linear tau"},
    {"psi_error_linear_tau", "psi_error_linear_tau", "average - exact", "Psi: average opacity - linear tau"},
};

std::string plots_json(const SegmentRulesStudy& st) {
  nlohmann::json plots = nlohmann::json::array();
  for (const auto& p : kUnitPlots) {
    const bool error = std::string(p[1]).find("error") != std::string::npos;
    plots.push_back({{"name", p[0]}, {"csv", "unit_segment.csv"}, {"style", "heatmap"}, {"x", "alpha_front"},
                     {"y", "alpha_back"}, {"z", p[1]}, {"zlabel", p[2]}, {"title", p[3]},
                     {"xlabel", "front opacity alpha_f"}, {"ylabel", "back opacity alpha_b"},
                     {"cmap", error ? "RdBu_r" : "viridis"}});
  }
  for (const RenderSpec& r : st.renders)
    plots.push_back({{"name", "convergence_" + r.name}, {"csv", "image_errors.csv"}, {"style", "lines"},
                     {"x", "step"}, {"y", "mean_error"}, {"group", "rule"}, {"where", {{"render", r.name}}},
                     {"xscale", "log"}, {"yscale", "log"}, {"fit", true}, {"xlabel", "step (world units)"},
                     {"ylabel", "mean |discrete - reference| over pixels"},
                     {"title", fmt::format("Image error against step: {}", r.name)}});
  return nlohmann::json{{"plots", plots}}.dump(2) + "\n";
}

StudyOutcome run_study(const SegmentRulesStudy& st, const StudyRun& run) {
  StudyOutcome out;
  const UnitSpec& u = st.unit;

  // Unit segment.
  const std::vector<UnitCell> cells = run_unit(u, run.quick, run.checkpoints);
  write_file_atomically(run.dir / "unit_segment.csv", unit_table(cells).to_csv());
  Table max_table({"model", "quantity", "max_abs_error", "signed_error", "alpha_front", "alpha_back",
                   "mean_abs_error", "stated_bound"});
  max_table.set_format("max_abs_error", "{:.4f}");
  max_table.set_format("signed_error", "{:.4f}");
  max_table.set_format("mean_abs_error", "{:.4f}");
  for (int model = 0; model < 2; ++model)
    for (int q = 0; q < 2; ++q) {
      const UnitSummary s = summarise(cells, model, q);
      const std::string what = fmt::format("{} {}", kQuantities[q], kModels[model]);
      max_table.add_row({std::string(kModels[model]), std::string(kQuantities[q]), s.max_error, s.signed_error,
                         s.at_f, s.at_b, s.mean_error, u.max_error[model][q]});
      out.checks.push_back({"identity " + what, s.diagonal, u.identity_tolerance, s.diagonal <= u.identity_tolerance,
                            "max |average - exact| where alpha_front = alpha_back (homogeneous segment)", CheckKind::identity});
      out.checks.push_back({"exact vs quadrature " + what, s.independent, u.independent_tolerance,
                            s.independent <= u.independent_tolerance,
                            "max |exact - nested Gauss-Kronrod of the defining integral| over the grid", CheckKind::derived});
      out.checks.push_back({"max error " + what, s.max_error, u.max_error[model][q], s.max_error <= u.max_error[model][q],
                            fmt::format("max |average - exact| over the grid, at alpha_f = {:g}, alpha_b = {:g}",
                                        s.at_f, s.at_b),
                            CheckKind::regression});
      if (model == 0)
        write_error_image(unit_error_image(cells, model, q), run.dir / fmt::format("{}_error_map", kQuantities[q]));
    }
  write_table(run.dir, "unit_segment_max", max_table,
              {"Largest error of the average-opacity approximation on a unit segment", "tab:segment-rules-max", {}});
  const long bad = non_finite(cells);
  out.checks.push_back({"non-finite unit-segment values", static_cast<double>(bad), 0, bad == 0,
                        "exact, approximate and quadrature zeta and Psi over the grid", CheckKind::derived});

  // Images.
  Table errors({"render", "rule", "step", "mean_error", "max_error", "samples_per_ray"});
  Table orders({"render", "rule", "expected_order", "observed_order", "pass"});
  orders.set_format("observed_order", "{:.3f}");
  Table maps({"render", "rule", "step", "max_abs_error", "file"});
  std::filesystem::create_directories(run.dir / "images");
  nlohmann::json renders = nlohmann::json::array();
  for (const RenderSpec& spec : st.renders) {
    const RenderResult res = run_render(spec, st.rules, st.strategy, st.reference_tol, run.audit, run.quick, run.progress,
                                           run.checkpoints, fmt::format("render{}", renders.size()));
    long bad_rows = 0;
    for (const ImageErrorRow& row : res.rows) {
      const bool finite = std::isfinite(row.mean_error) && std::isfinite(row.max_error);
      bad_rows += !finite;
      if (finite)
        errors.add_row({row.render, std::string(segment_rule_name(row.rule)), row.step, row.mean_error,
                        row.max_error, row.samples_per_ray});
    }
    out.checks.push_back({"finite image errors " + spec.name, static_cast<double>(bad_rows), 0, bad_rows == 0,
                          "(rule, step) rows whose mean or max image error is not finite", CheckKind::derived});
    const std::filesystem::path stem = run.dir / "images" / spec.name;
    write_value_image(res.reference, stem.string() + "_reference");
    for (std::size_t r = 0; r < st.rules.size(); ++r) {
      const std::string rule(segment_rule_name(st.rules[r].rule));
      const OrderEstimate& fit = res.fits[r];
      const double expected = st.rules[r].expected_order;
      const bool pass = order_matches(fit, expected, st.order_tolerance);
      orders.add_row({spec.name, rule, expected, std::isfinite(fit.order) ? fit.order : -1.0,
                      std::string(!spec.check_orders ? "not gated" : pass ? "yes" : "no")});
      if (spec.check_orders)
        out.checks.push_back(order_check(fmt::format("order {} {}", spec.name, rule), fit, expected, st.order_tolerance));
      const std::string file = fmt::format("images/{}_{}_error", spec.name, rule);
      write_error_image(res.error_maps[r], run.dir / file);
      maps.add_row({spec.name, rule, spec.map_step, max_abs_pixel(res.error_maps[r]), file + ".png"});
    }
    renders.push_back({{"name", spec.name}, {"width", res.width}, {"height", res.height},
                       {"hit_pixels", res.hit_pixels}, {"steps", run.quick ? spec.quick_steps : spec.steps},
                       {"map_step", spec.map_step}, {"scene", spec.scene_toml}});
  }
  write_file_atomically(run.dir / "image_errors.csv", errors.to_csv());
  write_table(run.dir, "orders", orders, {"Observed order of the image error per segment rule", "tab:segment-rules-orders", {}});
  write_table(run.dir, "error_maps", maps, {});
  write_file_atomically(run.dir / "plots.json", plots_json(st));

  const long n = run.quick ? u.quick_points : u.points;
  out.parameters = {{"grid_points", n}, {"alpha_top", u.alpha_top}, {"strategy", strategy_name(st.strategy)},
                    {"reference_tol", st.reference_tol}, {"renders", renders}};
  long failed = 0;
  for (const StudyCheck& c : out.checks) failed += !c.pass;
  out.summary = fmt::format("{}x{} unit-segment grid, {} renders x {} rules; {} of {} checks failed", n, n,
                            st.renders.size(), st.rules.size(), failed, out.checks.size());
  return out;
}

// The images' rays; the unit-segment grid casts none (closed forms and quadratures on n^2
// opacity pairs, a second or two) and is left out.
StudyWork study_work(const SegmentRulesStudy& st, bool quick) {
  StudyWork work;
  for (const RenderSpec& spec : st.renders) add_render_work(spec, st.rules, st.strategy, st.reference_tol, quick, work);
  return work;
}

StudyPlan parse_segment_rules(const StudyInput& in) {
  SegmentRulesStudy st = read_study(in);
  return {[st](const StudyRun& run) { return run_study(st, run); },
          [st](bool quick) { return study_work(st, quick); }};
}

const RegisterStudyKind kSegmentRules{"segment_rules", parse_segment_rules};

}  // namespace
}  // namespace vrv
