#include "studies/shading/shading.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "lib/io/atomic_file.h"
#include "lib/io/table.h"
#include "lib/metrics.h"
#include "lib/image_loop.h"
#include "lib/reference_integrator.h"
#include "lib/reference_pixels.h"
#include "lib/study_file.h"
#include "lib/gradient_scheme.h"
#include "lib/util/parallel.h"
#include "lib/work_estimate.h"
#include "studies/engine/study_outputs.h"
#include "studies/engine/study_rays.h"

namespace vrv {
namespace {

constexpr const char* kShadedNodes = "shaded_nodes";

// The study's schemes: every gradient scheme shading the samples, and shaded_nodes.
std::string scheme_list() { return gradient_scheme_list() + ", " + kShadedNodes; }

std::vector<ShadingScheme> read_schemes(const StudyReader& r, const toml::table& doc) {
  std::vector<ShadingScheme> out;
  const toml::array& a = r.array(r.require(doc, "schemes", ""), "schemes");
  if (a.empty()) r.fail("schemes", fmt::format("expected a non-empty array ({})", scheme_list()));
  for (std::size_t i = 0; i < a.size(); ++i) {
    const std::string path = fmt::format("schemes[{}]", i);
    const std::string name = r.string(*a.get(i), path);
    if (name == kShadedNodes) {
      out.push_back({GradientScheme::nodes, ShadeAt::nodes});
      continue;
    }
    const auto s = parse_gradient_scheme(name);
    if (!s) r.fail(path, fmt::format("unknown scheme '{}' ({})", name, scheme_list()));
    out.push_back({*s, ShadeAt::samples});
  }
  return out;
}

// The scene with its field replaced by an n^3 node grid of it (trilinear), its dims the grid's.
Scene grid_scene(const Scene& scene, int n) {
  Scene g = scene;
  const AnalyticField source = std::holds_alternative<LinearRamp>(scene.field)
                                   ? AnalyticField(std::get<LinearRamp>(scene.field))
                                   : AnalyticField(std::get<MarschnerLobb>(scene.field));
  g.field = make_grid(scene.box, source, {n, n, n}, GridLayout::node, Interpolation::trilinear);
  g.dims = {n, n, n};
  return g;
}

double grid_spacing(const Scene& scene, int n) { return scene.box.extent().minCoeff() / (n - 1); }

DiscreteConfig config_of(const ShadingStudy& study, const Scene& scene, const ShadingScheme& scheme, double step) {
  DiscreteConfig c;
  c.rule = study.rule;
  c.sampling.strategy = Strategy::step;
  c.sampling.step = step;
  c.sampling.dims = scene.dims;
  c.gradient = scheme.gradient;
  c.shade_at = scheme.shade_at;
  if (scheme.shade_at == ShadeAt::nodes) c.classification = Classification::pre;  // classes at the nodes
  return c;
}

struct References {
  std::vector<ReferenceResult> values;
};

References references(const Scene& scene, const std::vector<Ray>& rays, double tol, ShadingResult& out) {
  References r;
  r.values.resize(rays.size());
  parallel_for_index(static_cast<long>(rays.size()), [&](long i) { r.values[i] = integrate_reference(scene, rays[i], {tol}); });
  for (const ReferenceResult& v : r.values) out.truths.add(v);
  return r;
}

// |discrete - reference| over the rays that hit the box (a NaN is refused by error_stats, by name).
ErrorStats errors(const Scene& scene, const DiscreteConfig& config, const std::vector<Ray>& rays, const References& ref) {
  std::vector<double> e(rays.size());
  parallel_for_index(static_cast<long>(rays.size()), [&](long i) {
    e[i] = ref.values[i].hit ? discrete_raycast(scene, rays[i], config).value - ref.values[i].value : 0.0;
  });
  std::vector<double> hits;
  for (std::size_t i = 0; i < e.size(); ++i)
    if (ref.values[i].hit) hits.push_back(e[i]);
  return error_stats(hits, 0);
}

void step_refinement(const ShadingStudy& study, const std::vector<Ray>& rays, ShadingResult& out) {
  Scene unshaded = study.scene;
  unshaded.shading.reset();
  const References shaded_ref = references(study.scene, rays, study.reference_tol, out);
  const References unshaded_ref = references(unshaded, rays, study.reference_tol, out);
  std::vector<double> unshaded_errors;
  for (double h : study.steps)
    unshaded_errors.push_back(errors(unshaded, config_of(study, unshaded, {}, h), rays, unshaded_ref).mean);
  for (const ShadingScheme& scheme : study.schemes) {
    if (scheme.grid_only()) continue;
    std::vector<double> means;
    for (std::size_t k = 0; k < study.steps.size(); ++k) {
      const double h = study.steps[k];
      const ErrorStats e = errors(study.scene, config_of(study, study.scene, scheme, h), rays, shaded_ref);
      out.steps.push_back({scheme.name(), h, e.mean, e.max, unshaded_errors[k]});
      means.push_back(e.mean);
    }
    out.orders.push_back({"step", scheme.name(), estimate_order(study.steps, means)});
  }
}

void grid_refinement(const ShadingStudy& study, const std::vector<Ray>& rays, ShadingResult& out) {
  std::vector<double> spacings;
  std::vector<std::vector<double>> means(study.schemes.size());
  for (int n : study.grids) {
    const Scene grid = grid_scene(study.scene, n);
    const References ref = references(grid, rays, study.reference_tol, out);
    const double spacing = grid_spacing(study.scene, n), step = study.grid_step_per_spacing * spacing;
    spacings.push_back(spacing);
    for (std::size_t s = 0; s < study.schemes.size(); ++s) {
      const ErrorStats e = errors(grid, config_of(study, grid, study.schemes[s], step), rays, ref);
      out.grids.push_back({study.schemes[s].name(), n, spacing, step, e.mean, e.max});
      means[s].push_back(e.mean);
    }
  }
  for (std::size_t s = 0; s < study.schemes.size(); ++s)
    out.orders.push_back({"grid", study.schemes[s].name(), estimate_order(spacings, means[s])});
}

// The images' camera: the scene's (or the default), square at the study's size.
Camera image_camera(const ShadingStudy& study, bool quick) {
  Camera c = study.scene.camera ? *study.scene.camera : default_camera(study.scene.box);
  c.width = c.height = quick ? study.quick_image_size : study.image_size;
  return c;
}

// The reference per pixel and whether its ray hit the box, all the error maps need (verify's
// ReferenceImage, lib/verify/reference_image.h, also keeps estimates and depths).
struct TruthImage {
  std::vector<double> value;
  std::vector<char> hit;
};

// The reference at every pixel; its estimates and misses join the study's (in pixel order).
TruthImage truth_image(const Scene& scene, const Camera& camera, double tol, ShadingResult& out) {
  const auto n = static_cast<std::size_t>(camera.width) * static_cast<std::size_t>(camera.height);
  TruthImage r{std::vector<double>(n), std::vector<char>(n)};
  std::vector<double> estimate(n);
  std::vector<char> met(n);
  reference_pixels(scene, camera, {tol}, [&](long i, const ReferenceResult& v) {
    r.value[i] = v.value, r.hit[i] = v.hit, estimate[i] = v.error_estimate, met[i] = v.tolerance_met;
  });
  for (std::size_t i = 0; i < n; ++i) {
    out.truths.add(met[i], estimate[i]);
  }
  return r;
}

Image to_image(const std::vector<double>& v, const Camera& camera) {
  Image im(camera.width, camera.height);
  std::transform(v.begin(), v.end(), im.pixels.begin(), [](double x) { return static_cast<float>(x); });
  return im;
}

// The discrete raycast's signed error at every pixel, and its statistics over the hits.
std::pair<Image, ErrorStats> error_image(const Scene& scene, const Camera& camera, const DiscreteConfig& config,
                                         const TruthImage& ref) {
  std::vector<double> e = visit_field(scene, [&](const auto& field) {
    const auto caster = scene_raycaster(field, scene, config);
    return image_loop(camera, [&](const Ray& ray) { return caster.cast(ray).value; });
  });
  std::vector<double> hits;
  for (std::size_t i = 0; i < e.size(); ++i) {
    e[i] -= ref.value[i];
    if (ref.hit[i]) hits.push_back(e[i]);
  }
  return {to_image(e, camera), error_stats(hits, 0)};
}

// One field's images: its shaded reference, each scheme's error map at `step`, and with
// `unshaded` the unshaded raycast's against the unshaded reference; the maps share one colour bar.
void field_images(const ShadingStudy& study, const Scene& scene, const std::string& field, const std::string& stem,
                  const std::vector<ShadingScheme>& schemes, double step, bool unshaded, bool quick,
                  ShadingResult& out) {
  const Camera camera = image_camera(study, quick);
  const TruthImage ref = truth_image(scene, camera, study.reference_tol, out);
  out.images.push_back({stem + "_reference", to_image(ref.value, camera), false, 0});
  const std::size_t first_map = out.images.size();
  for (const ShadingScheme& scheme : schemes) {
    auto [map, stats] = error_image(scene, camera, config_of(study, scene, scheme, step), ref);
    const std::string name = scheme.name();
    out.image_rows.push_back({field, name, step, stats});
    out.images.push_back({fmt::format("{}_{}_error", stem, name), std::move(map), true, 0});
  }
  if (unshaded) {
    Scene plain = scene;
    plain.shading.reset();
    const TruthImage plain_ref = truth_image(plain, camera, study.reference_tol, out);
    auto [map, stats] = error_image(plain, camera, config_of(study, plain, {}, step), plain_ref);
    out.image_rows.push_back({field, "unshaded", step, stats});
    out.images.push_back({stem + "_unshaded_error", std::move(map), true, 0});
  }
  // One bar for the field's maps: the largest of their 99.5 % quantiles of |error| (a few pixels
  // beyond it, clamped, would otherwise wash the maps out).
  double range = 0;
  for (std::size_t k = first_map; k < out.images.size(); ++k)
    range = std::max(range, abs_pixel_quantile(out.images[k].pixels, 0.995));
  for (std::size_t k = first_map; k < out.images.size(); ++k) out.images[k].range = range;
}

void images(const ShadingStudy& study, bool quick, ShadingResult& out) {
  std::vector<ShadingScheme> analytic_schemes;
  for (const ShadingScheme& s : study.schemes)
    if (!s.grid_only()) analytic_schemes.push_back(s);
  field_images(study, study.scene, "analytic", "analytic", analytic_schemes, study.image_step, true, quick, out);
  const Scene grid = grid_scene(study.scene, study.image_grid);
  field_images(study, grid, fmt::format("grid {}^3", study.image_grid), fmt::format("grid{}", study.image_grid),
               study.schemes, study.image_step, false, quick, out);
}

constexpr const char* kShadingPlots = R"json({
  "plots": [
    {"name": "steps", "csv": "steps.csv", "style": "lines", "x": "step", "y": "mean_error",
     "group": "scheme", "xscale": "log", "yscale": "log", "fit": true,
     "xlabel": "step (world units)", "ylabel": "mean |discrete - shaded reference|",
     "title": "Shading: error against step (analytic field)"},
    {"name": "grids", "csv": "grids.csv", "style": "lines", "x": "spacing", "y": "mean_error",
     "group": "scheme", "xscale": "log", "yscale": "log", "fit": true,
     "xlabel": "grid spacing (world units)", "ylabel": "mean |discrete - shaded reference|",
     "title": "Shading: error against grid spacing"}
  ]
}
)json";

}  // namespace

std::string ShadingScheme::name() const {
  return shade_at == ShadeAt::nodes ? kShadedNodes : std::string(gradient_scheme_name(gradient));
}

ShadingStudy read_shading_study(const StudyInput& in) {
  const StudyReader& r = in.reader;
  const toml::table& doc = in.doc;
  r.check_keys(doc, "", {"name", "kind", "description", "order_tolerance", "reference_tol", "rays", "quick_rays", "seed",
                         "steps", "grids", "grid_step_per_spacing", "schemes", "method", "expected_order", "scene",
                         "image_size", "quick_image_size", "image_step", "image_grid"});
  ShadingStudy s;
  s.name = in.name;
  if (doc.contains("description")) s.description = r.string(*doc.get("description"), "description");
  if (doc.contains("order_tolerance")) s.order_tolerance = read_order_tolerance(r, doc, "");
  const RaySample sample = read_ray_sample(r, doc, {s.rays, s.quick_rays, s.seed, s.reference_tol});
  s.rays = sample.rays, s.quick_rays = sample.quick_rays, s.seed = sample.seed, s.reference_tol = sample.reference_tol;
  s.steps = read_refinement_steps(r, doc);
  for (long n : r.whole_numbers(doc, "grids", "", 3, 513)) s.grids.push_back(static_cast<int>(n));
  if (s.grids.size() < 3) r.fail("grids", "at least three grids (an order and its spread)");
  s.grid_step_per_spacing = r.number_or(doc, "grid_step_per_spacing", "", s.grid_step_per_spacing);
  if (!(s.grid_step_per_spacing > 0 && s.grid_step_per_spacing <= 4))
    r.fail("grid_step_per_spacing", fmt::format("must be in (0, 4], got {}", s.grid_step_per_spacing));
  s.schemes = read_schemes(r, doc);
  s.image_size = static_cast<int>(r.integer_or(doc, "image_size", "", 1, 4096, s.image_size));
  s.quick_image_size = static_cast<int>(r.integer_or(doc, "quick_image_size", "", 1, 4096, s.quick_image_size));
  s.image_step = r.number_or(doc, "image_step", "", s.image_step);
  if (!(s.image_step > 0 && std::isfinite(s.image_step)))
    r.fail("image_step", fmt::format("must be a positive finite length, got {}", s.image_step));
  s.image_grid = static_cast<int>(r.integer_or(doc, "image_grid", "", 3, 513, s.image_grid));
  if (doc.contains("method")) {
    s.rule = read_choice(r, *doc.get("method"), "method", all_segment_rules(), parse_segment_rule, segment_rule_name);
  }
  s.expected_order = r.number_or(doc, "expected_order", "", s.expected_order);
  std::string scene_toml;
  s.scene = read_study_scene(r, doc, "", scene_toml, true);
  if (!s.scene.shading) r.fail("scene", "needs a [scene.shading] table (the study compares shaded raycasts)");
  if (std::holds_alternative<GridField>(s.scene.field))
    r.fail("scene.field", "must be analytic (marschner_lobb or linear_ramp): the study samples it on its grids");
  return s;
}

ShadingResult run_shading(const ShadingStudy& study, bool quick) {
  ShadingResult out;
  out.rays = quick ? study.quick_rays : study.rays;
  const std::vector<Ray> rays = study_rays(study.scene.box, out.rays, study.seed);
  step_refinement(study, rays, out);
  grid_refinement(study, rays, out);
  images(study, quick, out);
  return out;
}

void write_shading(const std::filesystem::path& dir, const ShadingResult& result) {
  Table steps({"scheme", "step", "mean_error", "max_error", "unshaded_mean_error"});
  for (const char* c : {"mean_error", "max_error", "unshaded_mean_error"}) steps.set_format(c, "{:.3e}");
  for (const ShadingStepRow& r : result.steps)
    steps.add_row({r.scheme, r.step, r.mean_error, r.max_error, r.unshaded_mean_error});
  Table grids({"scheme", "nodes", "spacing", "step", "mean_error", "max_error"});
  for (const char* c : {"spacing", "step"}) grids.set_format(c, "{:.4g}");
  for (const char* c : {"mean_error", "max_error"}) grids.set_format(c, "{:.3e}");
  for (const ShadingGridRow& r : result.grids) grids.add_row({r.scheme, r.nodes, r.spacing, r.step, r.mean_error, r.max_error});
  Table orders({"refinement", "scheme", "observed", "standard_error"});
  orders.allow_missing("observed");
  orders.allow_missing("standard_error");
  orders.set_format("observed", "{:.2f}");
  orders.set_format("standard_error", "{:.2f}");
  for (const ShadingOrder& o : result.orders) orders.add_row({o.refinement, o.scheme, o.fit.order, o.fit.standard_error});
  write_table(dir, "steps", steps,
              {"Shading: error of each gradient scheme under step refinement (analytic field)", "tab:shading-steps", {}});
  write_table(dir, "grids", grids, {"Shading: error of each gradient scheme under grid refinement", "tab:shading-grids", {}});
  write_table(dir, "orders", orders, {"Shading: observed orders per gradient scheme", "tab:shading-orders", {}});
  Table image_errors({"field", "scheme", "step", "pixels", "max_error", "mean_error", "rms_error"});
  for (const char* c : {"max_error", "mean_error", "rms_error"}) image_errors.set_format(c, "{:.3e}");
  for (const ShadingImageRow& r : result.image_rows)
    image_errors.add_row({r.field, r.scheme, r.step, r.error.count, r.error.max, r.error.mean, r.error.rms});
  write_table(dir, "image_errors", image_errors,
              {"Shading: image error of each gradient scheme (pixels that hit the volume)", "tab:shading-images", {}});
  std::filesystem::create_directories(dir / "images");
  for (const ShadingImage& im : result.images)
    im.error ? write_error_image(im.pixels, dir / "images" / im.stem, im.range)
             : write_value_image(im.pixels, dir / "images" / im.stem);
  write_file_atomically(dir / "plots.json", kShadingPlots);
}

std::vector<StudyCheck> shading_checks(const ShadingStudy& study, const ShadingResult& result) {
  std::vector<StudyCheck> checks;
  for (const ShadingOrder& o : result.orders)
    if (o.refinement == "step" && o.scheme == "analytic")
      checks.push_back(order_check("order analytic (step refinement)", o.fit, study.expected_order, study.order_tolerance));
  double worst = 0;
  bool finite = true;
  for (const ShadingStepRow& r : result.steps) finite = finite && std::isfinite(r.mean_error) && std::isfinite(r.max_error), worst = std::max(worst, r.max_error);
  for (const ShadingGridRow& r : result.grids) finite = finite && std::isfinite(r.mean_error) && std::isfinite(r.max_error), worst = std::max(worst, r.max_error);
  for (const ShadingImageRow& r : result.image_rows)
    finite = finite && std::isfinite(r.error.mean) && std::isfinite(r.error.max), worst = std::max(worst, r.error.max);
  checks.push_back({"finite errors", worst, 0, finite, "every scheme's errors at every step and grid, and in every image, are finite",
                    CheckKind::finite});
  checks.push_back({"references within reference_tol", result.truths.largest_estimate, study.reference_tol,
                    result.truths.missed == 0,
                    fmt::format("largest error estimate of the shaded references; {} missed", result.truths.missed),
                    CheckKind::derived});
  return checks;
}

StudyWork shading_work(const ShadingStudy& study, bool quick) {
  StudyWork work;
  const double rays = static_cast<double>(quick ? study.quick_rays : study.rays);
  work.add("references", 2 * rays, reference_evaluations(study.scene, study.reference_tol));
  for (double h : study.steps)
    work.add(fmt::format("step {:g}", h), rays * static_cast<double>(study.schemes.size() + 1),
             discrete_samples(config_of(study, study.scene, {}, h), study.scene));
  const double pixels = std::pow(quick ? study.quick_image_size : study.image_size, 2);
  const Scene imaged = grid_scene(study.scene, study.image_grid);
  for (const Scene* scene : {&study.scene, &imaged}) {
    work.add("image references", 2 * pixels, reference_evaluations(*scene, study.reference_tol));
    work.add("images", pixels * static_cast<double>(study.schemes.size() + 1),
             discrete_samples(config_of(study, *scene, {}, study.image_step), *scene));
  }
  for (int n : study.grids) {
    const Scene grid = grid_scene(study.scene, n);
    work.add(fmt::format("grid {}^3 references", n), rays, reference_evaluations(grid, study.reference_tol));
    const DiscreteConfig c = config_of(study, grid, {}, study.grid_step_per_spacing * grid_spacing(study.scene, n));
    work.add(fmt::format("grid {}^3", n), rays * static_cast<double>(study.schemes.size()), discrete_samples(c, grid));
  }
  return work;
}

}  // namespace vrv
