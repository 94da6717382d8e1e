#include "lib/study_file.h"

#include "lib/option_error.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "lib/io/error_line.h"
#include "lib/scene_file.h"

namespace vrv {
namespace {
constexpr std::size_t kMaxStudyBytes = std::size_t{16} << 20;
constexpr double kMaxCaseSamples = 1e8;  // per discrete method and ray, a cap on run time

std::string scene_to_toml(const toml::table& scene) {
  std::ostringstream out;
  out << scene;
  return out.str();
}
}  // namespace

void StudyReader::fail(std::string_view key, std::string_view reason) const {
  throw StudyFileError(error_line(source_, key, reason));
}

void StudyReader::check_keys(const toml::table& t, std::string_view path,
                             std::initializer_list<std::string_view> allowed) const {
  for (const auto& [key, value] : t)
    if (std::find(allowed.begin(), allowed.end(), key.str()) == allowed.end())
      fail(child(path, key.str()), fmt::format("unknown key (allowed: {})", fmt::join(allowed, ", ")));
}

const toml::node& StudyReader::require(const toml::table& t, std::string_view key,
                                       std::string_view path) const {
  const toml::node* n = t.get(key);
  if (!n) fail(child(path, key), "missing");
  return *n;
}

const toml::table& StudyReader::table(const toml::node& n, std::string_view path) const {
  if (!n.is_table()) fail(path, "expected a table");
  return *n.as_table();
}

const toml::array& StudyReader::array(const toml::node& n, std::string_view path) const {
  if (!n.is_array()) fail(path, "expected an array");
  return *n.as_array();
}

std::string StudyReader::string(const toml::node& n, std::string_view path) const {
  if (!n.is_string()) fail(path, "expected a string");
  return std::string(n.as_string()->get());
}

double StudyReader::number(const toml::node& n, std::string_view path) const {
  double x;
  if (const auto* f = n.as_floating_point()) x = f->get();
  else if (const auto* i = n.as_integer()) x = static_cast<double>(i->get());
  else fail(path, "expected a number");
  if (!std::isfinite(x)) fail(path, fmt::format("must be finite, got {}", x));
  return x;
}

long StudyReader::integer(const toml::node& n, std::string_view path, long lo, long hi) const {
  const auto* i = n.as_integer();
  if (!i) fail(path, "expected an integer");
  if (i->get() < lo || i->get() > hi)
    fail(path, fmt::format("must be between {} and {}, got {}", lo, hi, i->get()));
  return static_cast<long>(i->get());
}

bool StudyReader::boolean(const toml::node& n, std::string_view path) const {
  if (!n.is_boolean()) fail(path, "expected true or false");
  return n.as_boolean()->get();
}

double StudyReader::number_or(const toml::table& t, std::string_view key, std::string_view path,
                              double def) const {
  const toml::node* n = t.get(key);
  return n ? number(*n, child(path, key)) : def;
}

long StudyReader::integer_or(const toml::table& t, std::string_view key, std::string_view path,
                             long lo, long hi, long def) const {
  const toml::node* n = t.get(key);
  return n ? integer(*n, child(path, key), lo, hi) : def;
}

std::vector<double> StudyReader::numbers(const toml::table& t, std::string_view key,
                                         std::string_view path, double lo, double hi) const {
  const std::string at = child(path, key);
  const toml::array& a = array(require(t, key, path), at);
  if (a.empty()) fail(at, "empty");
  std::vector<double> out;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const std::string p = fmt::format("{}[{}]", at, i);
    const double x = number(*a.get(i), p);
    if (!(x >= lo && x <= hi)) fail(p, fmt::format("must be in [{:g}, {:g}], got {:g}", lo, hi, x));
    out.push_back(x);
  }
  return out;
}

Vec3 StudyReader::vec3(const toml::table& t, std::string_view key, std::string_view path) const {
  const std::string at = child(path, key);
  const toml::array* a = require(t, key, path).as_array();
  if (!a || a->size() != 3) fail(at, "expected an array of three numbers");
  Vec3 v;
  for (std::size_t k = 0; k < 3; ++k) v[static_cast<int>(k)] = number(*a->get(k), fmt::format("{}[{}]", at, k));
  return v;
}

double StudyReader::order_tolerance(const toml::node& n, std::string_view path) const {
  const double tol = number(n, path);
  if (!(tol > 0 && tol <= kMaxOrderTolerance))
    fail(path, fmt::format("must be in (0, {:g}] (a wider band cannot tell order 1 from order 2), "
                           "got {:g}", kMaxOrderTolerance, tol));
  return tol;
}

std::string StudyReader::child(std::string_view path, std::string_view key) {
  return path.empty() ? std::string(key) : fmt::format("{}.{}", path, key);
}

toml::table parse_study_toml(std::string_view text, std::string_view source_name) {
  if (const auto problem = toml_nesting_problem(text))
    StudyReader(source_name).fail("(syntax)", *problem);
  try {
    return toml::parse(text, source_name);
  } catch (const toml::parse_error& e) {
    const auto& at = e.source().begin;
    StudyReader(source_name).fail("(syntax)", fmt::format("line {}, column {}: {}", at.line, at.column,
                                                          e.description()));
  }
}

std::string read_study_text(const std::filesystem::path& path) {
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
  return text.str();
}

namespace {

// scene = "FILE": a scene file, relative to the study file's folder; its errors are quoted whole.
Scene read_scene_file(const StudyReader& r, const std::string& at, const std::string& name,
                      std::string& toml_text) {
  const std::filesystem::path file =
      std::filesystem::path(r.source()).parent_path() / std::filesystem::path(name);
  std::error_code ec;
  if (name.empty() || !std::filesystem::is_regular_file(file, ec))
    r.fail(at, fmt::format("'{}' is not a scene file (a path relative to the study file: {})", name,
                           file.string()));
  toml_text = read_study_text(file);
  try {
    return parse_scene(toml_text, file.string());
  } catch (const SceneFileError& e) {
    throw StudyFileError(error_line(r.source(), at, e.what()));
  }
}

}  // namespace

namespace {

Scene read_any_study_scene(const StudyReader& r, const toml::table& parent, std::string_view path,
                           std::string& toml_text) {
  const std::string at = StudyReader::child(path, "scene");
  const toml::node& node = r.require(parent, "scene", path);
  if (const auto* name = node.as_string()) return read_scene_file(r, at, name->get(), toml_text);
  if (!node.is_table())
    r.fail(at, "expected a [scene] table or the path of a scene file (relative to the study file)");
  toml_text = scene_to_toml(*node.as_table());
  constexpr std::string_view marker = "\x01scene\x01";
  try {
    return parse_scene(toml_text, marker);
  } catch (const SceneFileError& e) {
    std::string msg = e.what();
    const std::string prefix = std::string(marker) + ": ";
    if (msg.starts_with(prefix)) msg = msg.substr(prefix.size());
    throw StudyFileError(one_line(fmt::format("{}: {}.{}", r.source(), at, msg)));
  }
}

}  // namespace

// Studies compare one channel so far: an RGB scene is refused by name.
Scene read_study_scene(const StudyReader& r, const toml::table& parent, std::string_view path,
                       std::string& toml_text, bool shaded) {
  Scene scene = read_any_study_scene(r, parent, path, toml_text);
  if (scene.color) r.fail(StudyReader::child(path, "scene"), "the scene is RGB (three-valued points), and studies compare one channel so far");
  if (scene.shading && !shaded)
    r.fail(StudyReader::child(path, "scene"), "the scene shades ([shading]): only the shading study shades so far");
  return scene;
}

// The renderer conventions of DiscreteConfig: opacity_unit = "sample" | "distance", color =
// "straight" | "premultiplied", table_size = N (0 or 2..2^20), table_lookup = "centred" | "uncentred".
void read_conventions(const StudyReader& r, const toml::table& m, const std::string& path, DiscreteConfig& c) {
  auto choice = [&](const char* key, auto parse, const char* choices, auto& out) {
    if (!m.contains(key)) return;
    const std::string text = r.string(*m.get(key), StudyReader::child(path, key));
    const auto v = parse(text);
    if (!v) r.fail(StudyReader::child(path, key), fmt::format("unknown value '{}' (one of {})", text, choices));
    out = *v;
  };
  choice("opacity_unit", parse_opacity_unit, "sample, distance", c.opacity_unit);
  choice("color", parse_color_convention, "straight, premultiplied", c.color);
  choice("table_lookup", parse_table_lookup, "centred, uncentred", c.table_lookup);
  if (m.contains("table_size"))
    c.table_size = static_cast<int>(r.integer(*m.get("table_size"), path + ".table_size", 0, kMaxTableSize));
}

std::string method_label(const StudyMethodSpec& m) {
  if (m.reference) return fmt::format("reference tol={:g}", m.tol);
  const DiscreteConfig& c = m.config;
  std::string label = fmt::format("{} {} {}={:g}", segment_rule_name(c.rule),
                                  strategy_name(c.sampling.strategy),
                                  step_based(c.sampling.strategy) ? "h" : "rate",
                                  step_based(c.sampling.strategy) ? c.sampling.step : c.sampling.rate);
  if (c.oversample != 1) label += fmt::format(" N={}", c.oversample);
  if (c.centred_oversamples) label += " centred";
  if (c.correction != Correction::none) label += fmt::format(" {}", correction_name(c.correction));
  if (c.opacity_unit != OpacityUnit::per_sample) label += " opacity/distance";
  if (c.color != ColorConvention::straight) label += fmt::format(" {}", color_convention_name(c.color));
  if (c.table_size > 0) label += fmt::format(" table={} {}", c.table_size, table_lookup_name(c.table_lookup));
  label += c.precision == Precision::single_precision ? " float" : " double";
  return label;
}

StudyMethodSpec read_study_method(const StudyReader& r, const toml::table& m, const std::string& path,
                                const Scene& scene) {
  r.check_keys(m, path, {"method", "label", "tol", "strategy", "rate", "step", "oversample", "centred_oversamples",
                         "correction", "precision", "max_error", "opacity_unit", "color", "table_size",
                         "table_lookup"});
  StudyMethodSpec out;
  const std::string name = r.string(r.require(m, "method", path), path + ".method");
  auto only_for_discrete = [&](std::initializer_list<std::string_view> keys) {
    for (std::string_view k : keys)
      if (m.contains(k)) r.fail(StudyReader::child(path, k), "not used by the reference method");
  };
  if (name == "reference") {
    only_for_discrete({"strategy", "rate", "step", "oversample", "centred_oversamples", "correction",
                       "precision", "max_error", "opacity_unit", "color", "table_size", "table_lookup"});
    out.reference = true;
    out.tol = r.number(r.require(m, "tol", path), path + ".tol");
    if (!(out.tol >= 1e-15 && out.tol <= 1))
      r.fail(path + ".tol", fmt::format("must be in [1e-15, 1], got {}", out.tol));
  } else {
    const auto rule = parse_segment_rule(name);
    if (!rule)
      r.fail(path + ".method", fmt::format("unknown method '{}' (one of reference, riemann, alpha, "
                                           "trapezoid, exact_linear, moreland)", name));
    if (m.contains("tol")) r.fail(path + ".tol", "only the reference method takes tol");
    DiscreteConfig& c = out.config;
    c.rule = *rule;
    const std::string strategy =
        r.string(r.require(m, "strategy", path), path + ".strategy");
    const auto st = parse_strategy(strategy);
    if (!st)
      r.fail(path + ".strategy", fmt::format("unknown strategy '{}' (one of eye, entry, entry_exit, "
                                             "entry_exit_corner, step, vtk, inviwo, partial, exit_anchored)", strategy));
    c.sampling.strategy = *st;
    c.sampling.dims = scene.dims;
    double samples;  // a bound on the samples per ray
    const double diagonal = scene.box.extent().norm();
    if (step_based(*st)) {
      if (m.contains("rate")) r.fail(path + ".rate", fmt::format("strategy {} takes step, not rate", strategy));
      c.sampling.step = r.number(r.require(m, "step", path), path + ".step");
      if (!(c.sampling.step > 0)) r.fail(path + ".step", fmt::format("must be positive, got {}", c.sampling.step));
      samples = diagonal / c.sampling.step;
    } else {
      if (m.contains("step")) r.fail(path + ".step", fmt::format("strategy {} takes rate, not step", strategy));
      c.sampling.rate = r.number(r.require(m, "rate", path), path + ".rate");
      if (!(c.sampling.rate > 0)) r.fail(path + ".rate", fmt::format("must be positive, got {}", c.sampling.rate));
      samples = c.sampling.rate * std::sqrt(3.0) *
                *std::max_element(scene.dims.begin(), scene.dims.end());
    }
    if (m.contains("oversample"))
      c.oversample = static_cast<int>(r.integer(*m.get("oversample"), path + ".oversample", 1, 65536));
    if (m.contains("centred_oversamples"))
      c.centred_oversamples = r.boolean(*m.get("centred_oversamples"), path + ".centred_oversamples");
    if (samples * c.oversample > kMaxCaseSamples)
      r.fail(path, fmt::format("about {:.3g} samples per ray (more than {:g})", samples * c.oversample,
                               kMaxCaseSamples));
    if (m.contains("correction")) {
      const std::string corr = r.string(*m.get("correction"), path + ".correction");
      const auto cc = parse_correction(corr);
      if (!cc)
        r.fail(path + ".correction", fmt::format("unknown correction '{}' (one of none, lacroute, "
                                                 "schulze, lee_newman, lee_newman_quadratic)", corr));
      c.correction = *cc;
    }
    if (m.contains("precision")) {
      const std::string prec = r.string(*m.get("precision"), path + ".precision");
      if (prec == "double") c.precision = Precision::double_precision;
      else if (prec == "float") c.precision = Precision::single_precision;
      else r.fail(path + ".precision", fmt::format("unknown precision '{}' (double or float)", prec));
    }
    read_conventions(r, m, path, c);
    if (m.contains("max_error")) {
      out.max_error = r.number(*m.get("max_error"), path + ".max_error");
      if (!(*out.max_error >= 0))
        r.fail(path + ".max_error", fmt::format("must not be negative, got {}", *out.max_error));
    }
    try {
      validate(c, std::holds_alternative<GridField>(scene.field), scene.transfer);
    } catch (const OptionError& e) {  // named by the key the file uses, not the command line's flag
      r.fail(StudyReader::child(path, option_name(e.option(), Spelling::key)), e.reason(Spelling::key));
    }
  }
  out.label = m.contains("label") ? r.string(*m.get("label"), path + ".label") : method_label(out);
  if (out.label.empty()) r.fail(path + ".label", "empty");
  return out;
}

nlohmann::json method_json(const StudyMethodSpec& m) {
  nlohmann::ordered_json j;
  j["label"] = m.label;
  if (m.reference) {
    j["method"] = "reference";
    j["tol"] = m.tol;
  } else {
    const DiscreteConfig& d = m.config;
    j["method"] = std::string(segment_rule_name(d.rule));
    j["strategy"] = std::string(strategy_name(d.sampling.strategy));
    if (step_based(d.sampling.strategy)) j["step"] = d.sampling.step;
    else j["rate"] = d.sampling.rate;
    j["oversample"] = d.oversample;
    j["centred_oversamples"] = d.centred_oversamples;
    j["correction"] = std::string(correction_name(d.correction));
    j["precision"] = d.precision == Precision::single_precision ? "float" : "double";
    // Renderer conventions only when not the defaults (earlier meta.json files stay as they were).
    if (d.opacity_unit != OpacityUnit::per_sample) j["opacity_unit"] = std::string(opacity_unit_name(d.opacity_unit));
    if (d.color != ColorConvention::straight) j["color"] = std::string(color_convention_name(d.color));
    if (d.table_size > 0) {
      j["table_size"] = d.table_size;
      j["table_lookup"] = std::string(table_lookup_name(d.table_lookup));
    }
    if (m.max_error) j["max_error"] = *m.max_error;
  }
  return nlohmann::json::parse(j.dump());
}

RaySample read_ray_sample(const StudyReader& r, const toml::table& doc, RaySample d) {
  RaySample s;
  s.reference_tol = r.number_or(doc, "reference_tol", "", d.reference_tol);
  if (!(s.reference_tol > 0)) r.fail("reference_tol", "must be positive");
  s.rays = r.integer_or(doc, "rays", "", 1, 100000, d.rays);
  s.quick_rays = r.integer_or(doc, "quick_rays", "", 1, 100000, d.quick_rays);
  s.seed = static_cast<std::uint64_t>(r.integer_or(doc, "seed", "", 0, 1L << 40, static_cast<long>(d.seed)));
  return s;
}

std::vector<double> read_refinement_steps(const StudyReader& r, const toml::table& doc) {
  std::vector<double> steps = r.numbers(doc, "steps", "", 1e-6, 1.0);
  if (steps.size() < 3) r.fail("steps", "at least three steps (an order and its spread)");
  return steps;
}

OrderTolerance read_order_tolerance(const StudyReader& r, const toml::table& parent, std::string_view path) {
  const std::string at = StudyReader::child(path, "order_tolerance");
  const toml::table& t = r.table(r.require(parent, "order_tolerance", path), at);
  r.check_keys(t, at, {"margin", "floor"});
  OrderTolerance o;
  o.margin = r.number(r.require(t, "margin", at), StudyReader::child(at, "margin"));
  o.floor = r.number(r.require(t, "floor", at), StudyReader::child(at, "floor"));
  // Bounded, so that no file can make an order gate that always passes: a margin of 10 standard
  // errors, or a floor of half an order, is already far past any honest tolerance.
  if (!(o.margin > 0 && o.margin <= 10)) r.fail(StudyReader::child(at, "margin"), "must be in (0, 10]");
  if (!(o.floor >= 0 && o.floor <= 0.5)) r.fail(StudyReader::child(at, "floor"), "must be in [0, 0.5]");
  return o;
}

}  // namespace vrv
