#include "lib/bounds_file.h"

#include <cmath>
#include <set>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "lib/camera.h"
#include "lib/study_file.h"

namespace vrv {
namespace {

namespace fs = std::filesystem;

// The generic strict TOML reader of the study files (lib/study_file.h): one-line errors naming
// file and key.
Limits read_limits(const StudyReader& r, const toml::node& n, std::string_view path, Bound b) {
  const toml::table& t = r.table(n, path);
  r.check_keys(t, path, {"warn", "fail", "hard_fail"});
  Limits l;
  if (const auto* v = t.get("warn")) l.warn = r.number(*v, StudyReader::child(path, "warn"));
  if (const auto* v = t.get("fail")) l.fail = r.number(*v, StudyReader::child(path, "fail"));
  if (const auto* v = t.get("hard_fail")) l.hard_fail = r.number(*v, StudyReader::child(path, "hard_fail"));
  if (!l.warn && !l.fail && !l.hard_fail) r.fail(path, "give at least one of warn, fail, hard_fail");
  // Levels in order of severity: each later one at least as far from "good" as the earlier.
  const bool lower = is_lower_limit(b);
  const std::optional<double> levels[] = {l.warn, l.fail, l.hard_fail};
  std::optional<double> prev;
  for (const auto& v : levels) {
    if (!v) continue;
    if (prev && (lower ? *v > *prev : *v < *prev))
      r.fail(path, fmt::format("levels must be ordered warn {} fail {} hard_fail", lower ? ">=" : "<=",
                               lower ? ">=" : "<="));
    prev = v;
  }
  if (!lower && prev && *prev < 0) r.fail(path, "limits must not be negative");
  return l;
}

constexpr std::string_view kBoundKeys[] = {"max", "mean", "rms", "p99", "percent_over", "min_order", "max_nan"};

void read_bound_set(const StudyReader& r, const toml::table& t, std::string_view path, BoundSet& set) {
  for (Bound b : kAllBounds)
    if (const auto* n = t.get(bound_name(b))) set.limits[b] = read_limits(r, *n, StudyReader::child(path, bound_name(b)), b);
  if (const auto* n = t.get("threshold")) {
    set.threshold = r.number(*n, StudyReader::child(path, "threshold"));
    if (set.threshold < 0) r.fail(StudyReader::child(path, "threshold"), "must be >= 0");
  }
  if (const auto* n = t.get("at")) {
    const std::string at = r.string(*n, StudyReader::child(path, "at"));
    if (at != "finest" && at != "all") r.fail(StudyReader::child(path, "at"), "must be \"finest\" or \"all\"");
    set.all_images = at == "all";
  }
}

// The options a render case takes: every discrete option but the case's own (its steps) and the
// ones a step rules out (rate) or vrv gate takes on its command line (max_work).
bool render_option(Option o) { return o != Option::step && o != Option::rate && o != Option::max_work; }

GateRenderSpec read_render(const StudyReader& r, const toml::node& n, std::string_view path) {
  const toml::table& t = r.table(n, path);
  static const std::vector<std::string_view> keys = [] {
    std::vector<std::string_view> k;
    for (const DiscreteOptionField& f : discrete_option_fields())
      if (render_option(f.option)) k.push_back(option_name(f.option, Spelling::key));
    return k;
  }();
  r.check_keys(t, path, keys);
  GateRenderSpec s;
  s.options.method = "alpha";
  s.options.strategy = "step";
  for (const DiscreteOptionField& f : discrete_option_fields())
    if (render_option(f.option))
      if (const toml::node* v = t.get(option_name(f.option, Spelling::key)))
        read_discrete_option(r, *v, StudyReader::child(path, option_name(f.option, Spelling::key)), f, s.options);
  return s;
}

// A case's name is the folder vrv gate writes it into (OUT/NAME/): one plain file-name component,
// never a path ("/abs/dir" wrote into /abs/dir, "../x" beside --out) nor a hidden name.
void check_case_name(const StudyReader& r, const std::string& name, std::string_view key) {
  constexpr std::size_t kMaxName = 100;
  if (name.empty()) r.fail(key, "empty");
  if (name.size() > kMaxName) r.fail(key, fmt::format("{} bytes, more than {}", name.size(), kMaxName));
  if (name.front() == '.') r.fail(key, fmt::format("'{}' begins with '.' (it names the folder OUT/NAME)", name));
  for (const char c : name)
    if (c == '/' || c == '\\' || static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      r.fail(key, fmt::format("'{}' is not a plain file name: no '/', '\\' or control characters (it names "
                              "the folder OUT/NAME)", name));
}

GateCase read_case(const StudyReader& r, const toml::table& t, std::string_view path, const BoundSet& defaults,
                   const fs::path& base) {
  r.check_keys(t, path, {"name", "scene", "steps", "expected_order", "render", "images", "study", "width",
                         "height", "threshold", "at", "max", "mean", "rms", "p99", "percent_over",
                         "min_order", "max_nan"});
  GateCase c;
  c.name = r.string(r.require(t, "name", path), StudyReader::child(path, "name"));
  check_case_name(r, c.name, StudyReader::child(path, "name"));
  c.bounds = defaults;
  read_bound_set(r, t, path, c.bounds);
  const int kinds = t.contains("render") + t.contains("images") + t.contains("study");
  if (kinds != 1) r.fail(path, "give exactly one of render, images, study");
  if (const auto* n = t.get("study")) {
    c.study = r.string(*n, StudyReader::child(path, "study"));
    for (std::string_view k : {"scene", "steps", "expected_order", "width", "height"})
      if (t.contains(k)) r.fail(StudyReader::child(path, k), "does not apply to a study case");
    return c;
  }
  if (const auto* n = t.get("scene")) c.scene = (base / r.string(*n, StudyReader::child(path, "scene"))).lexically_normal();
  // An images case may leave its steps to the images' provenance (vrv:step, read by vrv gate).
  if (t.contains("steps") || !t.contains("images")) c.steps = r.numbers(t, "steps", path, 0, 1e300);
  for (std::size_t i = 0; i < c.steps.size(); ++i)
    if (!(c.steps[i] > 0)) r.fail(fmt::format("{}.steps[{}]", path, i), "must be positive");
  if (const auto* n = t.get("expected_order")) c.expected_order = r.number(*n, StudyReader::child(path, "expected_order"));
  if (const auto* n = t.get("render")) {
    c.render = read_render(r, *n, StudyReader::child(path, "render"));
    if (t.contains("width")) c.width = static_cast<int>(r.integer(*t.get("width"), StudyReader::child(path, "width"), 1, kMaxImageSide));
    if (t.contains("height")) c.height = static_cast<int>(r.integer(*t.get("height"), StudyReader::child(path, "height"), 1, kMaxImageSide));
  } else {
    const toml::array& a = r.array(*t.get("images"), StudyReader::child(path, "images"));
    if (a.empty()) r.fail(StudyReader::child(path, "images"), "empty");
    for (std::size_t i = 0; i < a.size(); ++i)
      c.images.push_back((base / r.string(*a.get(i), fmt::format("{}.images[{}]", path, i))).lexically_normal());
    if (!c.steps.empty() && c.images.size() != c.steps.size())
      r.fail(StudyReader::child(path, "images"), fmt::format("{} images for {} steps", c.images.size(), c.steps.size()));
    for (std::string_view k : {"width", "height"})
      if (t.contains(k)) r.fail(StudyReader::child(path, k), "applies to render cases only (images have their size)");
  }
  return c;
}

}  // namespace

std::string_view bound_name(Bound b) { return kBoundKeys[static_cast<int>(b)]; }

BoundsFile parse_bounds(std::string_view text, const fs::path& source) {
  try {
    const StudyReader r(source.string());
    const toml::table doc = parse_study_toml(text, source.string());
    r.check_keys(doc, "", {"description", "defaults", "case"});
    BoundsFile f;
    f.path = source;
    if (const auto* n = doc.get("description")) f.description = r.string(*n, "description");
    if (const auto* n = doc.get("defaults")) {
      const toml::table& d = r.table(*n, "defaults");
      r.check_keys(d, "defaults", {"threshold", "at", "max", "mean", "rms", "p99", "percent_over",
                                   "min_order", "max_nan"});
      read_bound_set(r, d, "defaults", f.defaults);
    }
    const fs::path base = source.has_parent_path() ? source.parent_path() : fs::path(".");
    std::set<std::string> names;
    if (const auto* n = doc.get("case")) {
      const toml::array& cases = r.array(*n, "case");
      for (std::size_t i = 0; i < cases.size(); ++i) {
        const std::string path = fmt::format("case[{}]", i);
        GateCase c = read_case(r, r.table(*cases.get(i), path), path, f.defaults, base);
        if (!names.insert(c.name).second) r.fail(StudyReader::child(path, "name"), fmt::format("'{}' repeats", c.name));
        f.cases.push_back(std::move(c));
      }
    }
    return f;
  } catch (const StudyFileError& e) {
    throw BoundsFileError(e.what());
  }
}

const GateCase& named_case(const BoundsFile& file, const std::string& name) {
  for (const GateCase& c : file.cases)
    if (c.name == name) return c;
  throw std::invalid_argument(fmt::format("--case: {}: no case named '{}'", file.path.string(), name));
}

const BoundSet& chosen_bounds(const BoundsFile& file, const std::optional<std::string>& case_name) {
  return case_name ? named_case(file, *case_name).bounds : file.defaults;
}

BoundsFile load_bounds(const fs::path& path) {
  std::string text;
  std::error_code ec;
  if (!fs::exists(path, ec)) throw BoundsFileError(fmt::format("{}: (file): no such bounds file", path.string()));
  if (!fs::is_regular_file(path, ec))
    throw BoundsFileError(fmt::format("{}: (file): not a regular file (a bounds file is TOML text)", path.string()));
  try {
    text = read_study_text(path);
  } catch (const StudyFileError& e) {
    throw BoundsFileError(e.what());
  }
  return parse_bounds(text, path);
}

}  // namespace vrv
