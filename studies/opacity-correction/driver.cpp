// Study kind "opacity_correction": reading the study file (every key checked) and registering the
// kind; the run is run.cpp.  See docs/study-opacity-correction.md.
#include <algorithm>
#include <climits>

#include <fmt/format.h>

#include "studies/opacity-correction/opacity_correction.h"

namespace vrv {
namespace {

// The enum named at render.KEY (required): "must be a or b" otherwise.
template <class E, std::size_t N>
E required_name(const StudyReader& r, const toml::table& render, std::string_view key, const NameTable<E, N>& names) {
  const std::string path = fmt::format("render.{}", key);
  const std::string text = r.string(r.require(render, key, "render"), path);
  if (const auto value = parse_name(names, text)) return *value;
  r.fail(path, fmt::format("must be {}", name_list(names, " or ")));
}

bool has(const OpacityStudy& s, Correction c) {
  return std::find(s.corrections.begin(), s.corrections.end(), c) != s.corrections.end();
}

Correction correction_at(const StudyReader& r, const toml::node& n, const std::string& path) {
  const auto c = parse_correction(r.string(n, path));
  if (!c) r.fail(path, fmt::format("unknown correction ({})", correction_list()));
  return *c;
}

std::vector<int> factors(const StudyReader& r, const toml::table& t, std::string_view key, std::string_view path) {
  std::vector<int> out;
  const std::string at = StudyReader::child(path, key);
  const toml::array& a = r.array(r.require(t, key, path), at);
  if (a.empty()) r.fail(at, "empty");
  for (std::size_t i = 0; i < a.size(); ++i) out.push_back(static_cast<int>(r.integer(*a.get(i), fmt::format("{}[{}]", at, i), 1, 1024)));
  return out;
}

std::map<Correction, double> paper_values(const StudyReader& r, const toml::table& t, std::string_view path) {
  std::map<Correction, double> out;
  const std::string at = StudyReader::child(path, "paper");
  const toml::table& p = r.table(r.require(t, "paper", path), at);
  for (const auto& [key, node] : p) {
    const std::string k(key.str());
    const auto c = parse_correction(k);
    if (!c) r.fail(StudyReader::child(at, k), "unknown correction");
    out[*c] = r.number(node, StudyReader::child(at, k));
  }
  return out;
}

OpacityStudy read_study(const StudyInput& in) {
  const StudyReader& r = in.reader;
  const toml::table& doc = in.doc;
  r.check_keys(doc, "", {"kind", "name", "description", "corrections", "placements", "voxel", "surfaces", "fit", "scene", "render",
                         "sweep", "timing", "bounds"});
  OpacityStudy s;
  const toml::array& cs = r.array(r.require(doc, "corrections", ""), "corrections");
  for (std::size_t i = 0; i < cs.size(); ++i) s.corrections.push_back(correction_at(r, *cs.get(i), fmt::format("corrections[{}]", i)));
  for (Correction c : {Correction::none, Correction::lacroute, Correction::lee_newman})
    if (!has(s, c)) r.fail("corrections", fmt::format("must include {} (the paper's three)", correction_name(c)));

  const toml::array& ps = r.array(r.require(doc, "placements", ""), "placements");
  for (std::size_t i = 0; i < ps.size(); ++i) {
    const std::string at = fmt::format("placements[{}]", i), p = r.string(*ps.get(i), at);
    if (p != "first" && p != "centred") r.fail(at, "must be first or centred");
    s.placements.push_back(p == "centred");
  }
  if (s.placements.empty() || s.placements.front()) r.fail("placements", "must start with first (the paper's)");
  const toml::table& v = r.table(r.require(doc, "voxel", ""), "voxel");
  r.check_keys(v, "voxel", {"scale", "unit", "oversamples"});
  s.scale = r.number(r.require(v, "scale", "voxel"), "voxel.scale");
  if (!(s.scale > 0)) r.fail("voxel.scale", "must be positive");
  s.unit = r.number(r.require(v, "unit", "voxel"), "voxel.unit");
  if (!(s.unit >= 0 && s.unit <= s.scale)) r.fail("voxel.unit", "must be in [0, scale]");
  s.oversamples = r.numbers(v, "oversamples", "voxel", 0, s.scale);

  const toml::table& sf = r.table(r.require(doc, "surfaces", ""), "surfaces");
  r.check_keys(sf, "surfaces", {"csv_stride"});
  s.csv_stride = r.integer(r.require(sf, "csv_stride", "surfaces"), "surfaces.csv_stride", 1, 255);

  const toml::table& f = r.table(r.require(doc, "fit", ""), "fit");
  r.check_keys(f, "fit", {"N", "random_groups", "quick_random_groups", "seed", "threshold"});
  s.fit_N = factors(r, f, "N", "fit");
  s.fit_groups = r.integer(r.require(f, "random_groups", "fit"), "fit.random_groups", 1, 10'000'000);
  s.fit_quick_groups = r.integer(r.require(f, "quick_random_groups", "fit"), "fit.quick_random_groups", 1, 10'000'000);
  s.fit_seed = static_cast<std::uint64_t>(r.integer(r.require(f, "seed", "fit"), "fit.seed", 0, LONG_MAX));
  s.threshold = r.number(r.require(f, "threshold", "fit"), "fit.threshold");

  std::string scene_toml;
  s.scenes.analytic = read_study_scene(r, doc, "", scene_toml);
  if (std::holds_alternative<GridField>(s.scenes.analytic.field))
    r.fail("scene.field", "must be analytic: the render's grid is sampled from it (render.resolution)");
  if (s.scenes.analytic.transfer.convention() != Convention::opacity_color)
    r.fail("scene.transfer", "needs opacity and color (the paper's alpha = C = D / M per unit step)");
  if (!s.scenes.analytic.camera) r.fail("scene.camera", "missing (the render's view)");
  s.camera = *s.scenes.analytic.camera;
  s.scenes.unit_step = s.scenes.analytic.transfer.unit_length();

  const toml::table& rd = r.table(r.require(doc, "render", ""), "render");
  r.check_keys(rd, "render", {"resolution", "layout", "interpolation", "oversample", "reference_tol", "quick_width",
                              "quick_height", "error_map_quantile", "paper"});
  GridField::Index3 res{};
  const std::vector<long> rv = r.whole_numbers(rd, "resolution", "render", 2, 1024);
  if (rv.size() != 3) r.fail("render.resolution", "expected three whole numbers");
  for (int i = 0; i < 3; ++i) res[i] = static_cast<int>(rv[i]);
  const GridLayout layout = required_name(r, rd, "layout", kGridLayoutNames);
  const Interpolation interpolation = required_name(r, rd, "interpolation", kInterpolationNames);
  s.scenes.sampled = s.scenes.analytic;
  s.scenes.sampled.field = std::visit(
      [&](const auto& field) -> Field {
        using T = std::decay_t<decltype(field)>;
        if constexpr (std::is_same_v<T, GridField>) return field;
        else
          return make_grid(s.scenes.analytic.box, AnalyticField(field), res, layout, interpolation);
      },
      s.scenes.analytic.field);
  s.render_N = static_cast<int>(r.integer(r.require(rd, "oversample", "render"), "render.oversample", 1, 1024));
  s.scenes.reference_tol = read_reference_tol(r, rd, "render");
  s.quick_width = static_cast<int>(r.integer(r.require(rd, "quick_width", "render"), "render.quick_width", 1, 4096));
  s.quick_height = static_cast<int>(r.integer(r.require(rd, "quick_height", "render"), "render.quick_height", 1, 4096));
  s.error_map_quantile = r.number(r.require(rd, "error_map_quantile", "render"), "render.error_map_quantile");
  if (!(s.error_map_quantile > 0 && s.error_map_quantile <= 1)) r.fail("render.error_map_quantile", "must be in (0, 1]");
  s.paper_render = paper_values(r, rd, "render");

  const toml::table& sw = r.table(r.require(doc, "sweep", ""), "sweep");
  r.check_keys(sw, "sweep", {"N", "rays", "quick_rays", "seed"});
  s.sweep_N = factors(r, sw, "N", "sweep");
  if (s.sweep_N.front() != 1) r.fail("sweep.N", "must start at 1 (the identity check)");
  s.rays = r.integer(r.require(sw, "rays", "sweep"), "sweep.rays", 1, 1'000'000);
  s.quick_rays = r.integer(r.require(sw, "quick_rays", "sweep"), "sweep.quick_rays", 1, 1'000'000);
  s.sweep_seed = static_cast<std::uint64_t>(r.integer(r.require(sw, "seed", "sweep"), "sweep.seed", 0, LONG_MAX));

  const toml::table& tm = r.table(r.require(doc, "timing", ""), "timing");
  r.check_keys(tm, "timing", {"N", "groups", "quick_groups", "repeats", "quick_repeats", "width", "height",
                              "quick_width", "quick_height", "render_repeats", "quick_render_repeats", "paper"});
  const auto tint = [&](std::string_view key, long lo, long hi) {
    return r.integer(r.require(tm, key, "timing"), StudyReader::child("timing", key), lo, hi);
  };
  s.timing_N = static_cast<int>(tint("N", 1, 1024));
  s.timing_groups = tint("groups", 1, 10'000'000);
  s.timing_quick_groups = tint("quick_groups", 1, 10'000'000);
  s.repeats = static_cast<int>(tint("repeats", 1, 100));
  s.quick_repeats = static_cast<int>(tint("quick_repeats", 1, 100));
  s.timing_w = static_cast<int>(tint("width", 1, 4096));
  s.timing_h = static_cast<int>(tint("height", 1, 4096));
  s.timing_qw = static_cast<int>(tint("quick_width", 1, 4096));
  s.timing_qh = static_cast<int>(tint("quick_height", 1, 4096));
  s.render_repeats = static_cast<int>(tint("render_repeats", 1, 100));
  s.quick_render_repeats = static_cast<int>(tint("quick_render_repeats", 1, 100));
  const toml::table& tp = r.table(r.require(tm, "paper", "timing"), "timing.paper");
  r.check_keys(tp, "timing.paper", {"correction", "overall"});
  s.paper_correction = r.number(r.require(tp, "correction", "timing.paper"), "timing.paper.correction");
  s.paper_overall = r.number(r.require(tp, "overall", "timing.paper"), "timing.paper.overall");

  const toml::table& b = r.table(r.require(doc, "bounds", ""), "bounds");
  r.check_keys(b, "bounds", {"identity", "quadratic_exact_N2", "fit_mean_N5", "comparable", "plateau",
                             "order_tolerance"});
  s.b_identity = r.number(r.require(b, "identity", "bounds"), "bounds.identity");
  s.b_quadratic = r.number(r.require(b, "quadratic_exact_N2", "bounds"), "bounds.quadratic_exact_N2");
  s.b_fit_mean = r.number(r.require(b, "fit_mean_N5", "bounds"), "bounds.fit_mean_N5");
  s.b_comparable = r.number(r.require(b, "comparable", "bounds"), "bounds.comparable");
  s.b_plateau = r.number(r.require(b, "plateau", "bounds"), "bounds.plateau");
  s.order_tolerance = read_order_tolerance(r, b, "bounds");
  return s;
}

StudyPlan parse_opacity_study(const StudyInput& in) {
  const OpacityStudy study = read_opacity_study(in);
  return {[study](const StudyRun& run) { return run_opacity_study(study, run); },
          [study](bool quick) { return opacity_work(study, quick); }};
}

// [render]'s grid, sampled from the scene's analytic field.
std::vector<NodeCounts> opacity_grids(const toml::table& doc) {
  const toml::table* render = doc.get_as<toml::table>("render");
  const auto nodes = render ? node_counts_at(*render, "resolution") : std::nullopt;
  if (!nodes) return {};
  return {*nodes};
}

const RegisterStudyKind kOpacityCorrection{"opacity_correction", parse_opacity_study, opacity_grids};

}  // namespace

OpacityStudy read_opacity_study(const StudyInput& in) { return read_study(in); }

}  // namespace vrv
