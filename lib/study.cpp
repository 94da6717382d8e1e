#include "lib/study.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>
#include <random>
#include <sstream>
#include <type_traits>

#include <Eigen/Dense>
#include <fmt/format.h>
#include <toml++/toml.h>

#include "lib/atomic_file.h"
#include "lib/parallel.h"
#include "lib/progress.h"
#include "lib/reference_integrator.h"
#include "lib/run_metadata.h"
#include "lib/scene_file.h"
#include "lib/table.h"

namespace vrv {
namespace {

constexpr std::size_t kMaxStudyBytes = std::size_t{16} << 20;
constexpr long kMaxRays = 1'000'000;
constexpr std::size_t kMaxSteps = 64;

std::string one_line(std::string s) {
  std::replace_if(s.begin(), s.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
  return s;
}

class Reader {
 public:
  explicit Reader(std::string_view source) : source_(source) {}
  [[noreturn]] void fail(std::string_view key, std::string_view reason) const {
    throw StudyFileError(one_line(fmt::format("{}: {}: {}", source_, key, reason)));
  }
  void check_keys(const toml::table& t, std::string_view path,
                  std::initializer_list<std::string_view> allowed) const {
    for (const auto& [key, value] : t)
      if (std::find(allowed.begin(), allowed.end(), key.str()) == allowed.end())
        fail(child(path, key.str()),
             fmt::format("unknown key (allowed: {})", fmt::join(allowed, ", ")));
  }
  const toml::node& require(const toml::table& t, std::string_view key, std::string_view path) const {
    const toml::node* n = t.get(key);
    if (!n) fail(child(path, key), "missing");
    return *n;
  }
  const toml::table& table(const toml::node& n, std::string_view path) const {
    if (!n.is_table()) fail(path, "expected a table");
    return *n.as_table();
  }
  std::string string(const toml::node& n, std::string_view path) const {
    if (!n.is_string()) fail(path, "expected a string");
    return std::string(n.as_string()->get());
  }
  double number(const toml::node& n, std::string_view path) const {
    double x;
    if (const auto* f = n.as_floating_point()) x = f->get();
    else if (const auto* i = n.as_integer()) x = static_cast<double>(i->get());
    else fail(path, "expected a number");
    if (!std::isfinite(x)) fail(path, fmt::format("must be finite, got {}", x));
    return x;
  }
  long integer(const toml::node& n, std::string_view path, long lo, long hi) const {
    const auto* i = n.as_integer();
    if (!i) fail(path, "expected an integer");
    if (i->get() < lo || i->get() > hi)
      fail(path, fmt::format("must be between {} and {}, got {}", lo, hi, i->get()));
    return static_cast<long>(i->get());
  }
  static std::string child(std::string_view path, std::string_view key) {
    return path.empty() ? std::string(key) : fmt::format("{}.{}", path, key);
  }

 private:
  std::string source_;
};

std::string scene_to_toml(const toml::table& scene) {
  std::ostringstream out;
  out << scene;
  return out.str();
}

// Uniform in [0, 1) from the top 53 bits: the same on every platform.
double unit(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

}  // namespace

ConvergenceStudy parse_study(std::string_view text, std::string_view source_name,
                             std::string_view default_name) {
  const Reader r(source_name);
  toml::table doc;
  try {
    doc = toml::parse(text, source_name);
  } catch (const toml::parse_error& e) {
    const auto& at = e.source().begin;
    r.fail("(syntax)", fmt::format("line {}, column {}: {}", at.line, at.column, e.description()));
  }
  r.check_keys(doc, "", {"name", "kind", "description", "tolerance", "scene", "method", "sampling",
                         "rays", "reference_tol"});
  ConvergenceStudy s;
  s.source = std::string(source_name);
  const std::string kind = r.string(r.require(doc, "kind", ""), "kind");
  if (kind != "convergence")
    r.fail("kind", fmt::format("unknown kind '{}' (known: convergence)", kind));
  s.name = doc.contains("name") ? r.string(*doc.get("name"), "name") : std::string(default_name);
  if (s.name.empty() || s.name.find_first_of("/\\") != std::string::npos || s.name == "." ||
      s.name == "..")
    r.fail("name", fmt::format("'{}' is not a plain directory name", s.name));
  if (doc.contains("description")) s.description = r.string(*doc.get("description"), "description");
  if (doc.contains("tolerance")) {
    s.tolerance = r.number(*doc.get("tolerance"), "tolerance");
    if (!(s.tolerance > 0)) r.fail("tolerance", fmt::format("must be positive, got {}", s.tolerance));
  }
  if (doc.contains("reference_tol")) {
    s.reference_tol = r.number(*doc.get("reference_tol"), "reference_tol");
    if (!(s.reference_tol > 0))
      r.fail("reference_tol", fmt::format("must be positive, got {}", s.reference_tol));
  }

  // [scene]: the usual scene tables, parsed by parse_scene; its keys reported as scene.<key>.
  const toml::table& scene = r.table(r.require(doc, "scene", ""), "scene");
  s.scene_toml = scene_to_toml(scene);
  constexpr std::string_view marker = "\x01scene\x01";
  try {
    s.scene = parse_scene(s.scene_toml, marker);
  } catch (const SceneFileError& e) {
    std::string msg = e.what();
    const std::string prefix = std::string(marker) + ": ";
    if (msg.starts_with(prefix)) msg = msg.substr(prefix.size());
    throw StudyFileError(one_line(fmt::format("{}: scene.{}", source_name, msg)));
  }

  // [[method]]: rule and expected_order.
  const toml::node& methods = r.require(doc, "method", "");
  const toml::array* arr = methods.as_array();
  if (!arr) r.fail("method", "expected an array of tables ([[method]])");
  if (arr->empty()) r.fail("method", "no methods");
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const std::string path = fmt::format("method[{}]", i);
    const toml::table& m = r.table(*arr->get(i), path);
    r.check_keys(m, path, {"rule", "expected_order"});
    const std::string name = r.string(r.require(m, "rule", path), path + ".rule");
    const auto rule = parse_segment_rule(name);
    if (!rule)
      r.fail(path + ".rule", fmt::format("unknown method '{}' (one of riemann, alpha, trapezoid, "
                                         "exact_linear, moreland)", name));
    for (const StudyMethod& earlier : s.methods)
      if (earlier.rule == *rule) r.fail(path + ".rule", fmt::format("'{}' is listed twice", name));
    const double order = r.number(r.require(m, "expected_order", path), path + ".expected_order");
    if (!(order > 0)) r.fail(path + ".expected_order", fmt::format("must be positive, got {}", order));
    s.methods.push_back({*rule, order});
  }

  // [sampling]: strategy and steps.
  const toml::table& sampling = r.table(r.require(doc, "sampling", ""), "sampling");
  r.check_keys(sampling, "sampling", {"strategy", "steps"});
  const std::string strategy = r.string(r.require(sampling, "strategy", "sampling"), "sampling.strategy");
  const auto st = parse_strategy(strategy);
  if (!st || (*st != Strategy::step && *st != Strategy::inviwo))
    r.fail("sampling.strategy",
           fmt::format("unknown or unsupported strategy '{}' (step or inviwo)", strategy));
  s.strategy = *st;
  const toml::node& steps = r.require(sampling, "steps", "sampling");
  const toml::array* sa = steps.as_array();
  if (!sa) r.fail("sampling.steps", "expected an array of numbers");
  if (sa->empty()) r.fail("sampling.steps", "empty (give at least two steps)");
  if (sa->size() < 2) r.fail("sampling.steps", "one step gives no order (give at least two)");
  if (sa->size() > kMaxSteps) r.fail("sampling.steps", fmt::format("more than {} steps", kMaxSteps));
  for (std::size_t i = 0; i < sa->size(); ++i) {
    const std::string path = fmt::format("sampling.steps[{}]", i);
    const double h = r.number(*sa->get(i), path);
    if (!(h > 0)) r.fail(path, fmt::format("must be positive, got {}", h));
    if (std::find(s.steps.begin(), s.steps.end(), h) != s.steps.end())
      r.fail(path, fmt::format("step {} is listed twice", h));
    s.steps.push_back(h);
  }

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

ConvergenceStudy load_study(const std::filesystem::path& path) {
  const std::string source = path.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw StudyFileError(one_line(fmt::format("{}: (file): no such study file", source)));
  if (std::filesystem::file_size(path, ec) > kMaxStudyBytes)
    throw StudyFileError(one_line(fmt::format("{}: (file): larger than 16 MiB", source)));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw StudyFileError(one_line(fmt::format("{}: (file): cannot read", source)));
  std::ostringstream text;
  text << in.rdbuf();
  return parse_study(text.str(), source, path.stem().string());
}

std::vector<Ray> study_rays(const Box& box, long count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const Vec3 centre = 0.5 * (box.min + box.max);
  const double radius = 3 * 0.5 * box.extent().norm();
  std::vector<Ray> rays;
  rays.reserve(static_cast<std::size_t>(count));
  for (long i = 0; i < count; ++i) {
    const double z = 2 * unit(rng) - 1;
    const double phi = 2 * std::numbers::pi * unit(rng);
    const double rho = std::sqrt(std::max(0.0, 1 - z * z));
    const Vec3 origin = centre + radius * Vec3(rho * std::cos(phi), rho * std::sin(phi), z);
    Vec3 target;
    for (int k = 0; k < 3; ++k) target[k] = box.min[k] + unit(rng) * (box.max[k] - box.min[k]);
    rays.push_back(make_ray(origin, target - origin));
  }
  return rays;
}

double observed_order(const std::vector<double>& steps, const std::vector<double>& errors) {
  if (steps.size() < 2 || steps.size() != errors.size()) return std::numeric_limits<double>::quiet_NaN();
  Eigen::MatrixXd A(steps.size(), 2);
  Eigen::VectorXd b(steps.size());
  for (std::size_t i = 0; i < steps.size(); ++i) {
    if (!(errors[i] > 0) || !std::isfinite(errors[i])) return std::numeric_limits<double>::quiet_NaN();
    A(static_cast<Eigen::Index>(i), 0) = std::log(steps[i]);
    A(static_cast<Eigen::Index>(i), 1) = 1;
    b(static_cast<Eigen::Index>(i)) = std::log(errors[i]);
  }
  return A.colPivHouseholderQr().solve(b)(0);
}

StudyResult run_convergence(const ConvergenceStudy& study, bool quick, bool progress) {
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
        DiscreteConfig c;
        c.rule = m.rule;
        c.sampling.strategy = study.strategy;
        c.sampling.step = h;
        c.sampling.dims = study.scene.dims;
        validate(c, std::is_same_v<F, GridField>);
        casters.emplace_back(field, study.scene.box, study.scene.transfer, study.scene.background, c);
      }
    Progress bar("study " + study.name, n, progress);
    parallel_for_index(n, [&](long i) {
      const Ray& ray = rays[static_cast<std::size_t>(i)];
      const double reference = integrate_reference(field, study.scene.box, study.scene.transfer,
                                                   study.scene.background, ray,
                                                   {study.reference_tol}).value;
      for (std::size_t k = 0; k < per_ray; ++k) {
        const DiscreteResult d = casters[k].cast(ray);
        error[static_cast<std::size_t>(i) * per_ray + k] = std::abs(d.value - reference);
        samples[static_cast<std::size_t>(i) * per_ray + k] = d.samples;
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
    OrderRow o{study.methods[m].rule, study.methods[m].expected_order,
               observed_order(study.steps, means), false};
    o.pass = std::isfinite(o.observed) && std::abs(o.observed - o.expected) <= study.tolerance;
    result.pass = result.pass && o.pass;
    result.orders.push_back(o);
  }
  return result;
}

StudyFiles study_tables(const ConvergenceStudy& study, const StudyResult& result) {
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
  style.caption = fmt::format("Observed convergence orders ({} rays, tolerance {:g}).", result.rays,
                              study.tolerance);
  style.label = "tab:" + study.name;
  return {errors.to_csv(), orders.to_csv(), orders.to_markdown(), orders.to_latex(style)};
}

nlohmann::json study_parameters(const ConvergenceStudy& study, bool quick, int threads) {
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
  p["tolerance"] = study.tolerance;
  p["reference_tol"] = study.reference_tol;
  p["quick"] = quick;
  p["threads"] = threads;  // recorded only; no number depends on it
  return nlohmann::json::parse(p.dump());
}

void write_study(const std::filesystem::path& dir, const ConvergenceStudy& study,
                 const StudyResult& result, const nlohmann::json& parameters, double seconds) {
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
  nlohmann::json meta = run_metadata(parameters, seconds);
  meta["pass"] = result.pass;
  write_file_atomically(dir / "meta.json", meta.dump(2) + "\n");
}

}  // namespace vrv
