#include "lib/study_file.h"

#include "lib/option_error.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <span>
#include <type_traits>
#include <variant>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "lib/discrete_options.h"
#include "lib/io/error_line.h"
#include "lib/scene_file.h"
#include "lib/scene_mode.h"
#include "lib/volume/volume_grid.h"

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
  check_keys(t, path, std::span<const std::string_view>(allowed.begin(), allowed.size()));
}

void StudyReader::check_keys(const toml::table& t, std::string_view path, std::span<const std::string_view> allowed) const {
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

double StudyReader::positive(const toml::node& n, std::string_view path) const {
  const double x = number(n, path);
  if (!(x > 0)) fail(path, fmt::format("must be positive, got {}", x));
  return x;
}

double StudyReader::non_negative(const toml::node& n, std::string_view path) const {
  const double x = number(n, path);
  if (!(x >= 0)) fail(path, fmt::format("must be >= 0, got {}", x));
  return x;
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

void StudyReader::fail_repeat(std::string_view at, std::size_t index, double value) const {
  fail(fmt::format("{}[{}]", at, index), fmt::format("{} is listed twice", value));
}

std::vector<long> StudyReader::whole_numbers(const toml::table& t, std::string_view key,
                                             std::string_view path, long lo, long hi) const {
  const std::vector<double> x = numbers(t, key, path, static_cast<double>(lo), static_cast<double>(hi));
  std::vector<long> out;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (x[i] != std::floor(x[i]))
      fail(fmt::format("{}[{}]", child(path, key), i), fmt::format("expected a whole number, got {}", x[i]));
    out.push_back(static_cast<long>(x[i]));
  }
  return out;
}

void StudyReader::fail_choice(std::string_view path, std::string_view text, bool known,
                              std::span<const std::string_view> names) const {
  const std::string list = fmt::format("{}", fmt::join(names, ", "));
  fail(path, known ? fmt::format("'{}' is not taken here (one of {})", text, list)
                   : fmt::format("unknown value '{}' (one of {})", text, list));
}

void StudyReader::spend_memory(std::string_view key, std::string_view what, double bytes) const {
  if (limited_ && !(bytes <= memory_left_))
    fail(key, fmt::format("{} needs {:.1f} MiB, more than the {:.1f} MiB the study has left under its memory limit "
                          "(raise it with --max-memory GIB)",
                          what, bytes / (1 << 20), memory_left_ / (1 << 20)));
  memory_left_ -= bytes;
  memory_spent_ += bytes;
}

void StudyReader::note_scene(std::string_view key, bool rgb) const {
  if (rgb ? saw_grey_ : saw_rgb_)
    fail(key, fmt::format("the scene is {} and an earlier one {}: a study's scenes are all grey or all RGB (an RGB "
                          "study is one study per channel)", rgb ? "RGB" : "grey", rgb ? "grey" : "RGB"));
  (rgb ? saw_rgb_ : saw_grey_) = true;
}

void StudyReader::require_grey_scenes() const {
  if (saw_rgb_)
    fail("scene", "the scene is RGB (three-valued points), which this reader takes one channel of: run it with vrv "
                  "study (one study per channel)");
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

// The bytes of the grid a scene file's [field] declares, from its text before it is parsed (as the
// study's own estimate counts its [scene] tables' grids); 0 for none, or for a file parse_scene
// will refuse anyway.
double declared_grid_bytes(std::string_view text) {
  if (toml_nesting_problem(text)) return 0;
  try {
    const toml::table doc = toml::parse(text);
    const toml::table* field = doc.get_as<toml::table>("field");
    const auto nodes = field ? field_grid_nodes(*field) : std::nullopt;
    return nodes ? grid_bytes(*nodes) : 0;
  } catch (const toml::parse_error&) {
    return 0;
  }
}

// scene = "FILE": a scene file, relative to the study file's folder; its errors are quoted whole.
// Its grid is spent from the study's memory before it is built (a study of many scene files
// could otherwise hold more grids than its limit allows).
Scene read_scene_file(const StudyReader& r, const std::string& at, const std::string& name,
                      std::string& toml_text) {
  const std::filesystem::path file =
      std::filesystem::path(r.source()).parent_path() / std::filesystem::path(name);
  std::error_code ec;
  if (name.empty() || !std::filesystem::is_regular_file(file, ec))
    r.fail(at, fmt::format("'{}' is not a scene file (a path relative to the study file: {})", name,
                           file.string()));
  toml_text = read_study_text(file);
  r.spend_memory(at, fmt::format("the grid of {}", file.string()), declared_grid_bytes(toml_text));
  try {
    return parse_scene(toml_text, file.string(), r.volume_budget());
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
  // The source name parse_scene's messages start with, replaced by the study file's key below
  // (printable: messages write control bytes as \xNN).
  constexpr std::string_view marker = "(the study's inline scene)";
  try {
    return parse_scene(toml_text, marker, r.volume_budget());
  } catch (const SceneFileError& e) {
    std::string msg = e.what();
    const std::string prefix = std::string(marker) + ": ";
    if (msg.starts_with(prefix)) msg = msg.substr(prefix.size());
    throw StudyFileError(one_line(fmt::format("{}: {}.{}", r.source(), at, msg)));
  }
}

}  // namespace

// An RGB scene is read as one of its channels (the reader's, else red) and noted: the loader then
// studies each channel (studies/engine/channel_study.h).
Scene read_study_scene(const StudyReader& r, const toml::table& parent, std::string_view path,
                       std::string& toml_text, bool shaded) {
  Scene scene = read_any_study_scene(r, parent, path, toml_text);
  if (const auto mode = scene_mode(toml_text))
    r.fail(StudyReader::child(path, "scene"), projection_refusal(*mode, "the studies do"));
  // A volume's reader checked its size against what was left: now it is held.
  if (!scene.field_files.empty())
    r.spend_memory(StudyReader::child(path, "scene"), "the volume " + digest_file_names(scene.field_files),
                   static_cast<double>(std::get<GridField>(scene.field).nodes().bytes()));
  if (scene.shading && !shaded)
    r.fail(StudyReader::child(path, "scene"), "the scene shades ([shading]): only the shading study shades so far");
  r.note_scene(StudyReader::child(path, "scene"), scene.color.has_value());
  if (!scene.color) return scene;
  return channel_scene(scene, r.channel().value_or(0));
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
  if (c.classification == Classification::pre) label += " pre-classified";
  if (c.compositing == Compositing::back_to_front) label += fmt::format(" {}", compositing_name(c.compositing));
  if (c.termination) label += fmt::format(" termination={:g}", *c.termination);
  if (c.skip_below) label += fmt::format(" skip<{:g}", *c.skip_below);
  label += fmt::format(" {}", precision_name(c.precision));
  return label;
}

void read_discrete_option(const StudyReader& r, const toml::node& n, const std::string& at,
                          const DiscreteOptionField& f, DiscreteOptions& opt) {
  std::visit(
      [&](auto member) {
        using T = std::remove_reference_t<decltype(opt.*member)>;
        if constexpr (std::is_same_v<T, bool>) opt.*member = r.boolean(n, at);
        else if constexpr (std::is_same_v<T, int>)
          opt.*member = static_cast<int>(r.integer(n, at, std::numeric_limits<int>::min(), std::numeric_limits<int>::max()));
        else if constexpr (std::is_same_v<T, std::string> || std::is_same_v<T, std::optional<std::string>>)
          opt.*member = r.string(n, at);
        else opt.*member = r.number(n, at);
      },
      f.member);
  if (f.needs_method) opt.give(f.option, "");
}

namespace {

// The discrete options a study's method takes, as the file spells them: every option of
// lib/discrete_options.h but method (read first) and max_work (a study has its own work limit).
bool study_option(const DiscreteOptionField& f) { return f.option != Option::method && f.option != Option::max_work; }

std::vector<std::string_view> study_method_keys() {
  std::vector<std::string_view> keys = {"method", "label", "tol", "max_error"};
  for (const DiscreteOptionField& f : discrete_option_fields())
    if (study_option(f)) keys.push_back(option_name(f.option, Spelling::key));
  return keys;
}

// A discrete method's configuration: its options read as lib/discrete_options.h declares them and
// checked by discrete_config, the command line's own checks, each failure named by the file's key.
// A study states its placement: strategy and the rate or step it takes are required.
DiscreteConfig read_discrete_method(const StudyReader& r, const toml::table& m, const std::string& path,
                                    const std::string& method, const Scene& scene) {
  DiscreteOptions opt;
  opt.method = method;
  for (const DiscreteOptionField& f : discrete_option_fields())
    if (study_option(f))
      if (const toml::node* n = m.get(option_name(f.option, Spelling::key)))
        read_discrete_option(r, *n, StudyReader::child(path, option_name(f.option, Spelling::key)), f, opt);
  r.require(m, "strategy", path);
  if (const auto st = parse_strategy(*opt.strategy)) r.require(m, step_based(*st) ? "step" : "rate", path);
  try {
    return *discrete_config(opt, scene);
  } catch (const OptionError& e) {  // named by the key the file uses, not the command line's flag
    r.fail(StudyReader::child(path, option_name(e.option(), Spelling::key)), e.reason(Spelling::key));
  }
}

}  // namespace

StudyMethodSpec read_study_method(const StudyReader& r, const toml::table& m, const std::string& path,
                                  const Scene& scene) {
  static const std::vector<std::string_view> keys = study_method_keys();
  r.check_keys(m, path, keys);
  StudyMethodSpec out;
  const std::string name = r.string(r.require(m, "method", path), path + ".method");
  if (name == "reference") {
    for (const std::string_view key : std::span(keys).subspan(3))  // all but method, label and tol
      if (m.contains(key)) r.fail(StudyReader::child(path, key), "not used by the reference method");
    out.reference = true;
    out.tol = r.number(r.require(m, "tol", path), path + ".tol");
    if (!(out.tol >= 1e-15 && out.tol <= 1))
      r.fail(path + ".tol", fmt::format("must be in [1e-15, 1], got {}", out.tol));
  } else {
    if (!parse_segment_rule(name))
      r.fail(path + ".method", fmt::format("unknown method '{}' (one of reference, {})", name, segment_rule_list()));
    if (m.contains("tol")) r.fail(path + ".tol", "only the reference method takes tol");
    out.config = read_discrete_method(r, m, path, name, scene);
    const DiscreteConfig& c = out.config;
    // A bound on the samples per ray.
    const double samples = step_based(c.sampling.strategy)
                               ? scene.box.extent().norm() / c.sampling.step
                               : c.sampling.rate * std::sqrt(3.0) * *std::max_element(scene.dims.begin(), scene.dims.end());
    if (samples * c.oversample > kMaxCaseSamples)
      r.fail(path, fmt::format("about {:.3g} samples per ray (more than {:g})", samples * c.oversample,
                               kMaxCaseSamples));
    if (m.contains("max_error")) {
      out.max_error = r.number(*m.get("max_error"), path + ".max_error");
      if (!(*out.max_error >= 0))
        r.fail(path + ".max_error", fmt::format("must not be negative, got {}", *out.max_error));
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
    j["precision"] = std::string(precision_name(d.precision));
    // Renderer conventions only when not the defaults (earlier meta.json files stay as they were).
    if (d.opacity_unit != OpacityUnit::per_sample) j["opacity_unit"] = std::string(opacity_unit_name(d.opacity_unit));
    if (d.color != ColorConvention::straight) j["color"] = std::string(color_convention_name(d.color));
    if (d.table_size > 0) {
      j["table_size"] = d.table_size;
      j["table_lookup"] = std::string(table_lookup_name(d.table_lookup));
    }
    // Options only where not the defaults, likewise.
    if (d.classification == Classification::pre) j["classification"] = std::string(classification_name(d.classification));
    if (d.compositing == Compositing::back_to_front) j["compositing"] = std::string(compositing_name(d.compositing));
    if (d.termination) j["termination"] = *d.termination;
    if (d.skip_below) j["skip"] = *d.skip_below;
    if (m.max_error) j["max_error"] = *m.max_error;
  }
  return nlohmann::json::parse(j.dump());
}

double read_reference_tol(const StudyReader& r, const toml::table& t, std::string_view path,
                          std::optional<double> fallback) {
  constexpr double kLoosest = 1e-6;
  const toml::node* n = t.get("reference_tol");
  if (!n && fallback) return *fallback;
  const std::string at = StudyReader::child(path, "reference_tol");
  const double tol = r.number(n ? *n : r.require(t, "reference_tol", path), at);
  if (!(tol > 0 && tol <= kLoosest)) r.fail(at, fmt::format("must be in (0, {:g}], got {:g}", kLoosest, tol));
  return tol;
}

RaySample read_ray_sample(const StudyReader& r, const toml::table& doc, RaySample d) {
  RaySample s;
  s.reference_tol = read_reference_tol(r, doc, "", d.reference_tol);
  s.rays = r.integer_or(doc, "rays", "", 1, 100000, d.rays);
  s.quick_rays = r.integer_or(doc, "quick_rays", "", 1, 100000, d.quick_rays);
  s.seed = static_cast<std::uint64_t>(r.integer_or(doc, "seed", "", 0, 1L << 40, static_cast<long>(d.seed)));
  return s;
}

std::vector<double> read_refinement_steps(const StudyReader& r, const toml::table& doc) {
  std::vector<double> steps = r.numbers(doc, "steps", "", 1e-6, 1.0);
  r.check_distinct(steps, "", "steps");
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
