#pragma once
// Reading study files (TOML): every problem is one line, "<file>: <key path>: <reason>", thrown as
// StudyFileError, so that `vrv study` can print it and exit 2.  Shared by every study kind: the
// reader with path-aware errors, the [scene] table (parsed by the scene-file parser) and the one
// way a method is written in a study ({method = "reference", tol} or a discrete configuration).
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <optional>
#include <stdexcept>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include "lib/discrete_options.h"
#include "lib/discrete_raycast.h"
#include "lib/geometry.h"
#include "lib/order_estimate.h"
#include "lib/scene.h"

namespace vrv {

// A bad study file: one line, "<file>: <key>: <reason>".
class StudyFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

inline constexpr double kMaxOrderTolerance = 0.5;

class StudyReader {
 public:
  // memory_left: the bytes the study may still spend on grids its file's memory estimate
  // (studies/engine/memory_budget.h) cannot see before they are read: volume files, and the grids
  // of `scene = "FILE"` scene files; 0 for no limit but the readers' own caps.
  explicit StudyReader(std::string_view source, double memory_left = 0)
      : source_(source), limited_(memory_left > 0), memory_left_(memory_left) {}
  const std::string& source() const { return source_; }
  // What a volume read now may take, as parse_scene's max_volume_bytes: 0 without a limit.
  double volume_budget() const { return limited_ ? std::max(memory_left_, 1.0) : 0.0; }
  // Spends `bytes` on the grid `what` at key `key`, or fails naming both when they are more than
  // is left (without a limit, only counts them).
  void spend_memory(std::string_view key, std::string_view what, double bytes) const;
  // What spend_memory has spent: the grids the file's estimate could not see.
  double memory_spent() const { return memory_spent_; }
  [[noreturn]] void fail(std::string_view key, std::string_view reason) const;
  void check_keys(const toml::table& t, std::string_view path,
                  std::initializer_list<std::string_view> allowed) const;
  void check_keys(const toml::table& t, std::string_view path, std::span<const std::string_view> allowed) const;
  const toml::node& require(const toml::table& t, std::string_view key, std::string_view path) const;
  const toml::table& table(const toml::node& n, std::string_view path) const;
  const toml::array& array(const toml::node& n, std::string_view path) const;
  std::string string(const toml::node& n, std::string_view path) const;
  double number(const toml::node& n, std::string_view path) const;  // finite
  // number(), and > 0 ("must be positive, got X") or >= 0 ("must be >= 0, got X"): orders, steps,
  // and the tolerances of checks (a negative one is a check that cannot pass).
  double positive(const toml::node& n, std::string_view path) const;
  double non_negative(const toml::node& n, std::string_view path) const;
  long integer(const toml::node& n, std::string_view path, long lo, long hi) const;
  bool boolean(const toml::node& n, std::string_view path) const;
  // Optional keys: the default when absent.
  double number_or(const toml::table& t, std::string_view key, std::string_view path, double def) const;
  long integer_or(const toml::table& t, std::string_view key, std::string_view path, long lo, long hi,
                  long def) const;
  // A non-empty array of finite numbers, each in [lo, hi].
  std::vector<double> numbers(const toml::table& t, std::string_view key, std::string_view path,
                              double lo, double hi) const;
  // Fails at "<path.key>[i]" when entry i repeats an earlier one ("V is listed twice"): lists of
  // refinement levels (steps, resolutions), where a repeat is a typo that puts two of an order's
  // points in one place.
  template <class T>
  void check_distinct(const std::vector<T>& values, std::string_view path, std::string_view key) const {
    for (std::size_t i = 1; i < values.size(); ++i)
      if (std::find(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(i), values[i]) !=
          values.begin() + static_cast<std::ptrdiff_t>(i))
        fail_repeat(child(path, key), i, static_cast<double>(values[i]));
  }
  // The same, each a whole number (written 17 or 17.0): grid sizes, node counts.
  std::vector<long> whole_numbers(const toml::table& t, std::string_view key, std::string_view path, long lo,
                                  long hi) const;
  Vec3 vec3(const toml::table& t, std::string_view key, std::string_view path) const;
  // Fails at `path` for `text`, which should have been one of `names`: "unknown value 'X' (one of
  // a, b)", or, when `known` (X names something this key does not take here), "'X' is not taken
  // here (one of a, b)".
  [[noreturn]] void fail_choice(std::string_view path, std::string_view text, bool known,
                                std::span<const std::string_view> names) const;
  // A gate's band on |observed order - expected order|: in (0, kMaxOrderTolerance].  A wider band
  // cannot tell order 1 from order 2, and tolerance = 1e308 made a gate pass whatever happened.
  double order_tolerance(const toml::node& n, std::string_view path) const;
  static std::string child(std::string_view path, std::string_view key);
  [[noreturn]] void fail_repeat(std::string_view at, std::size_t index, double value) const;
  // The channel of an RGB scene this read is for (studies/engine/channel_study.h): read_study_scene
  // then gives that channel's grey scene.  Every scene read is noted, so a read without a channel
  // tells the loader to study each channel (saw_rgb_scene), and a file mixing grey and RGB scenes
  // is refused (note_scene).
  void set_channel(int channel) { channel_ = channel; }
  std::optional<int> channel() const { return channel_; }
  bool saw_rgb_scene() const { return saw_rgb_; }
  // Fails at `key` when the scene is RGB and an earlier one grey, or the other way round: an RGB
  // study is one study per channel, of which a grey scene would be three copies.
  void note_scene(std::string_view key, bool rgb) const;
  // Fails at "scene" when an RGB scene was read: for the readers that parse a study file outside
  // `vrv study` (which alone runs one study per channel), so that none is reduced to red.
  void require_grey_scenes() const;

 private:
  std::string source_;
  bool limited_;
  // Readers are passed as const everywhere; spending the budget is the one change a read makes.
  mutable double memory_left_;
  mutable double memory_spent_ = 0;
  std::optional<int> channel_;
  mutable bool saw_rgb_ = false, saw_grey_ = false;
};

// The study file parsed as TOML (syntax errors as "<file>: (syntax): line L, column C: ...").
toml::table parse_study_toml(std::string_view text, std::string_view source_name);
// Reads the file (must exist, at most 16 MiB) into `text`.
std::string read_study_text(const std::filesystem::path& path);

// The value of an enum E named by the string `n` at `path`, one of `allowed` (`parse` and `name`
// are E's name table's, lib/util/enum_names.h); else fail_choice, naming the allowed ones.
template <class E>
E read_choice(const StudyReader& r, const toml::node& n, std::string_view path, std::span<const E> allowed,
              std::optional<E> (*parse)(std::string_view), std::string_view (*name)(E)) {
  const std::string text = r.string(n, path);
  const std::optional<E> value = parse(text);
  if (value && std::find(allowed.begin(), allowed.end(), *value) != allowed.end()) return *value;
  std::vector<std::string_view> names;
  for (E e : allowed) names.push_back(name(e));
  r.fail_choice(path, text, value.has_value(), names);
}

// A non-empty list of them at `t[key]` (under `path`), none twice.
template <class E>
std::vector<E> read_choices(const StudyReader& r, const toml::table& t, std::string_view key, std::string_view path,
                            std::span<const E> allowed, std::optional<E> (*parse)(std::string_view),
                            std::string_view (*name)(E)) {
  const std::string at = StudyReader::child(path, key);
  const toml::array& a = r.array(r.require(t, key, path), at);
  if (a.empty()) r.fail(at, "empty");
  std::vector<E> out;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const std::string item = at + "[" + std::to_string(i) + "]";
    const E value = read_choice(r, *a.get(i), item, allowed, parse, name);
    if (std::find(out.begin(), out.end(), value) != out.end()) r.fail(item, "listed twice");
    out.push_back(value);
  }
  return out;
}


// The [scene] table under `parent` (at `path`): the usual scene tables, parsed by parse_scene, its
// keys reported as <path>.scene.<key>; its TOML text goes to `toml_text`.  Or `scene = "FILE"`:
// a scene file, relative to the study file's folder (its own errors name it); its text goes to
// `toml_text`.
// A shaded scene ([shading]) is refused unless `shaded` (the studies whose raycasts shade).  An RGB
// scene is its channel r.channel() (red without one), noted on the reader (saw_rgb_scene).
Scene read_study_scene(const StudyReader& r, const toml::table& parent, std::string_view path,
                       std::string& toml_text, bool shaded = false);

// One discrete option (lib/discrete_options.h) from its key's node, read as the type its field
// holds (a string, a number, an integer, true or false), into `opt`, recorded as given; `at` is the
// key's path for errors.  Its value is checked later, by discrete_config.
void read_discrete_option(const StudyReader& r, const toml::node& n, const std::string& at,
                          const DiscreteOptionField& f, DiscreteOptions& opt);

// A method as a study writes it: the reference integrator at `tol`, or a discrete raycast.
struct StudyMethodSpec {
  std::string label;              // `label` key, else built from the configuration
  bool reference = false;
  double tol = 1e-13;             // reference
  DiscreteConfig config;          // discrete
  std::optional<double> max_error;  // discrete: a stated bound on its error
};

// Keys: method (reference | riemann | alpha | trapezoid | exact_linear | moreland), label, tol
// (reference), max_error (discrete), and every discrete option of lib/discrete_options.h but
// max_work, spelled as keys (strategy, step | rate, oversample, centred_oversamples, correction,
// termination, skip, compositing, classification, precision, opacity_unit, color, table_size,
// table_lookup, and for shaded scenes gradient, gradient_offset, shade_at): the command line's
// values and checks, except that strategy and its rate or step are required.  Checked against the
// scene (grid-only options, a cap of 1e8 samples per ray).
StudyMethodSpec read_study_method(const StudyReader& r, const toml::table& m, const std::string& path,
                                  const Scene& scene);
// "alpha step h=0.01 N=4 lacroute double", "reference tol=1e-10".
std::string method_label(const StudyMethodSpec& m);
// The method as JSON (for meta.json parameters).
nlohmann::json method_json(const StudyMethodSpec& m);

// `order_tolerance = { margin = M, floor = F }` under `parent` (lib/order_estimate.h): M > 0, F >= 0.
OrderTolerance read_order_tolerance(const StudyReader& r, const toml::table& parent, std::string_view path);

// `reference_tol` under `t` at `path`: the absolute tolerance of a study's truths, one rule for
// every study: a finite number in (0, 1e-6] (a looser truth could not resolve the errors a study
// measures).  Tighter than double arithmetic can certify is allowed: the study's
// reference_within_tolerance check then reports the truths that miss it.  `fallback`: its value
// when the key is absent; without one the key is required.
double read_reference_tol(const StudyReader& r, const toml::table& t, std::string_view path,
                          std::optional<double> fallback = std::nullopt);

// The rays a ray-sampled study casts, each key optional (the given default when absent):
// rays and quick_rays in [1, 100000], seed in [0, 2^40], reference_tol (read_reference_tol).
struct RaySample {
  long rays = 64, quick_rays = 16;
  std::uint64_t seed = 0;
  double reference_tol = 1e-13;
};
RaySample read_ray_sample(const StudyReader& r, const toml::table& doc, RaySample defaults);
// `steps = [...]`: at least three (an order and its spread), each in [1e-6, 1].
std::vector<double> read_refinement_steps(const StudyReader& r, const toml::table& doc);

}  // namespace vrv
