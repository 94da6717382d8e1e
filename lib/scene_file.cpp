#include "lib/scene_file.h"

#include "lib/io/error_line.h"
#include "lib/projection/projection_mode.h"
#include "lib/util/enum_names.h"
#include "lib/volume/volume_file.h"
#include "lib/volume/volume_grid.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <toml++/toml.h>

namespace vrv {
namespace {

constexpr std::string_view kDefaultScene = R"(# Marschner-Lobb test signal with a linear emission/extinction ramp.
[volume]
min = [-1.0, -1.0, -1.0]
max = [1.0, 1.0, 1.0]
dims = [64, 64, 64]

[field]
kind = "marschner_lobb"
fM = 6.0
alpha = 0.25

[transfer]
emission = [[0.0, 0.0], [1.0, 1.0]]
extinction = [[0.0, 0.0], [1.0, 0.5]]

[background]
intensity = 0.0
)";

// Caps so that a hostile file cannot exhaust memory or time.
constexpr std::int64_t kMaxAxis = 1 << 16;
constexpr std::int64_t kMaxGridNodes = std::int64_t{1} << 27;  // 1 GiB of doubles
constexpr std::size_t kMaxFileBytes = std::size_t{16} << 20;

std::string child(std::string_view path, std::string_view key) {
  return path.empty() ? std::string(key) : fmt::format("{}.{}", path, key);
}

std::string element(std::string_view path, std::size_t i) { return fmt::format("{}[{}]", path, i); }

std::string_view type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::table: return "a table";
    case toml::node_type::array: return "an array";
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a float";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::date:
    case toml::node_type::time:
    case toml::node_type::date_time: return "a date/time";
    default: return "nothing";
  }
}

// Reads typed values and reports every problem as "<source>: <path>: <reason>".
class Reader {
 public:
  explicit Reader(std::string_view source, double volume_budget = 0)
      : source_(source), volume_budget_(volume_budget) {}

  // Bytes a volume file's samples and grid may take (0: only the grid cap).
  double volume_budget() const { return volume_budget_; }

  // Keys, strings and file names may carry line breaks or be megabytes long: one short line.
  [[noreturn]] void fail(std::string_view path, std::string_view reason) const {
    throw SceneFileError(error_line(source_, path, reason));
  }

  void check_keys(const toml::table& t, std::string_view path,
                  std::initializer_list<std::string_view> allowed) const {
    for (const auto& [key, value] : t)
      if (std::find(allowed.begin(), allowed.end(), key.str()) == allowed.end())
        fail(child(path, key.str()), fmt::format("unknown key (allowed: {})", fmt::join(allowed, ", ")));
  }

  const toml::node& require(const toml::table& t, std::string_view key, std::string_view path) const {
    const toml::node* n = t.get(key);
    if (!n) fail(child(path, key), "missing");
    return *n;
  }

  const toml::table& table(const toml::node& n, std::string_view path) const {
    if (!n.is_table()) fail(path, fmt::format("expected a table, got {}", type_name(n)));
    return *n.as_table();
  }

  const toml::table* optional_table(const toml::table& t, std::string_view key,
                                    std::string_view path) const {
    const toml::node* n = t.get(key);
    return n ? &table(*n, child(path, key)) : nullptr;
  }

  const toml::array& array(const toml::node& n, std::string_view path) const {
    if (!n.is_array()) fail(path, fmt::format("expected an array, got {}", type_name(n)));
    return *n.as_array();
  }

  const toml::array& array(const toml::node& n, std::string_view path, std::size_t size) const {
    const toml::array& a = array(n, path);
    if (a.size() != size) fail(path, fmt::format("expected {} elements, got {}", size, a.size()));
    return a;
  }

  // Integers are accepted as numbers; nan and inf are not.
  double number(const toml::node& n, std::string_view path) const {
    double x = 0;
    if (const auto* i = n.as_integer()) x = static_cast<double>(i->get());
    else if (const auto* f = n.as_floating_point()) x = f->get();
    else fail(path, fmt::format("expected a number, got {}", type_name(n)));
    if (!std::isfinite(x)) fail(path, fmt::format("{} is not a finite number", x));
    return x;
  }

  double number_or(const toml::table& t, std::string_view key, std::string_view path,
                   double fallback) const {
    const toml::node* n = t.get(key);
    return n ? number(*n, child(path, key)) : fallback;
  }

  // A positive integer up to kMaxAxis; floats are rejected.
  int count(const toml::node& n, std::string_view path) const {
    const auto* i = n.as_integer();
    if (!i) fail(path, fmt::format("expected an integer, got {}", type_name(n)));
    const std::int64_t v = i->get();
    if (v < 1) fail(path, fmt::format("must be positive, got {}", v));
    if (v > kMaxAxis) fail(path, fmt::format("too large, got {} (at most {})", v, kMaxAxis));
    return static_cast<int>(v);
  }

  std::string_view string(const toml::node& n, std::string_view path) const {
    const auto* s = n.as_string();
    if (!s) fail(path, fmt::format("expected a string, got {}", type_name(n)));
    return s->get();
  }

  Vec3 vec3(const toml::node& n, std::string_view path) const {
    const toml::array& a = array(n, path, 3);
    Vec3 v;
    for (std::size_t i = 0; i < 3; ++i) v[i] = number(*a.get(i), element(path, i));
    return v;
  }

  std::array<int, 3> int3(const toml::node& n, std::string_view path) const {
    const toml::array& a = array(n, path, 3);
    std::array<int, 3> v{};
    for (std::size_t i = 0; i < 3; ++i) v[i] = count(*a.get(i), element(path, i));
    return v;
  }

  // [[v, y], ...] with non-decreasing v, each value at most twice (twice is a jump); with
  // `channels` = 3 also [[v, r, g, b], ...] (all points alike).  One curve per channel given.
  std::vector<std::vector<ControlPoint>> points(const toml::node& n, std::string_view path, int channels = 1) const {
    const toml::array& a = array(n, path);
    if (a.empty()) fail(path, "empty array (needs at least one control point)");
    std::vector<std::vector<ControlPoint>> curves;
    for (std::size_t i = 0; i < a.size(); ++i) {
      const std::string p = element(path, i);
      const toml::array* point = a.get(i)->as_array();
      const std::size_t size = point ? point->size() : 0;
      if (curves.empty() && (size == 2 || (channels == 3 && size == 4))) curves.resize(size - 1);
      if (size != curves.size() + 1 || curves.empty()) {
        const std::string got = point ? fmt::format("{} numbers", size) : std::string(type_name(*a.get(i)));
        if (!curves.empty() && channels == 3)
          fail(p, fmt::format("expected [value, {}] as the first point, got {}", curves.size() == 1 ? "y" : "r, g, b", got));
        fail(p, fmt::format("expected a pair [value, y]{}, got {}", channels == 3 ? " or [value, r, g, b]" : "", got));
      }
      const double v = number(*point->get(0), element(p, 0));
      for (std::size_t c = 0; c < curves.size(); ++c)
        curves[c].push_back({v, number(*point->get(c + 1), element(p, c + 1))});
      const std::vector<ControlPoint>& pts = curves[0];
      if (i > 0 && pts[i].v < pts[i - 1].v)
        fail(p, fmt::format("control values out of order: {} after {}", pts[i].v, pts[i - 1].v));
      if (i > 1 && pts[i].v == pts[i - 2].v)
        fail(p, fmt::format("value {} appears more than twice (a jump takes exactly two)", pts[i].v));
    }
    return curves;
  }

  // One of the enum's named values (its table beside its declaration), or `fallback` without the key.
  template <class E, std::size_t N>
  E choice(const toml::table& t, std::string_view key, std::string_view path, const NameTable<E, N>& names,
           E fallback) const {
    const toml::node* n = t.get(key);
    if (!n) return fallback;
    const std::string p = child(path, key);
    const std::string_view s = string(*n, p);
    if (const auto value = parse_name(names, s)) return *value;
    fail(p, fmt::format("unknown value \"{}\" (expected {})", s, name_list(names, " or ")));
  }

 private:
  std::string_view source_;
  double volume_budget_ = 0;
};

Box read_box(const Reader& r, const toml::table& t) {
  Box box;
  box.min = r.vec3(r.require(t, "min", "volume"), "volume.min");
  box.max = r.vec3(r.require(t, "max", "volume"), "volume.max");
  for (std::size_t a = 0; a < 3; ++a)
    if (!(box.min[a] < box.max[a]))
      r.fail(element("volume.max", a),
             fmt::format("max {} must exceed min {}", box.max[a], box.min[a]));
  if (!box.extent().allFinite()) r.fail("volume", "box extent overflows");
  return box;
}

MarschnerLobb read_marschner_lobb(const Reader& r, const toml::table& t, std::string_view path) {
  r.check_keys(t, path, {"kind", "fM", "alpha"});
  MarschnerLobb f;
  f.fM = r.number_or(t, "fM", path, f.fM);
  f.alpha = r.number_or(t, "alpha", path, f.alpha);
  // A negative fM would make the bandwidth bound negative; alpha <= -1 divides by zero.
  if (f.fM < 0) r.fail(child(path, "fM"), fmt::format("must not be negative, got {}", f.fM));
  if (f.alpha < 0) r.fail(child(path, "alpha"), fmt::format("must not be negative, got {}", f.alpha));
  return f;
}

LinearRamp read_linear_ramp(const Reader& r, const toml::table& t, std::string_view path) {
  r.check_keys(t, path, {"kind", "gradient", "offset"});
  LinearRamp f;
  f.gradient = r.vec3(r.require(t, "gradient", path), child(path, "gradient"));
  f.offset = r.number_or(t, "offset", path, f.offset);
  return f;
}

// The analytic field kinds, each its name (the type's own, analytic/*.h) and its reader, once: a
// new analytic field is a row here (it holds no nodes: field_grid_nodes has none for it).  The
// grid kinds are kGridKinds, below.
struct AnalyticKind {
  std::string_view name;
  AnalyticField (*read)(const Reader& r, const toml::table& t, std::string_view path);
};
constexpr AnalyticKind kAnalyticKinds[] = {
    {MarschnerLobb::kind, [](const Reader& r, const toml::table& t, std::string_view path) -> AnalyticField {
       return read_marschner_lobb(r, t, path);
     }},
    {LinearRamp::kind, [](const Reader& r, const toml::table& t, std::string_view path) -> AnalyticField {
       return read_linear_ramp(r, t, path);
     }},
};
static_assert(std::size(kAnalyticKinds) == std::variant_size_v<AnalyticField>, "a reader for every analytic field");

std::string_view read_kind(const Reader& r, const toml::table& t, std::string_view path) {
  return r.string(r.require(t, "kind", path), child(path, "kind"));
}

const AnalyticKind* analytic_kind(std::string_view name) {
  for (const AnalyticKind& k : kAnalyticKinds)
    if (k.name == name) return &k;
  return nullptr;
}

struct GridKind;
const GridKind* grid_kind(std::string_view name);
[[noreturn]] void unknown_kind(const Reader& r, std::string_view path, std::string_view kind);

AnalyticField read_source(const Reader& r, const toml::table& t, std::string_view path) {
  const std::string_view kind = read_kind(r, t, path);
  if (const AnalyticKind* k = analytic_kind(kind)) return k->read(r, t, path);
  if (grid_kind(kind))
    r.fail(child(path, "kind"), fmt::format("nested {}: a grid source must be an analytic field", kind));
  unknown_kind(r, path, kind);
}

GridField read_grid(const Reader& r, const toml::table& t, const Box& box) {
  r.check_keys(t, "field", {"kind", "source", "resolution", "layout", "interpolation"});
  const AnalyticField source =
      read_source(r, r.table(r.require(t, "source", "field"), "field.source"), "field.source");
  const auto layout = r.choice(t, "layout", "field", kGridLayoutNames, GridLayout::node);
  const auto interpolation = r.choice(t, "interpolation", "field", kInterpolationNames, Interpolation::trilinear);
  const auto res = r.int3(r.require(t, "resolution", "field"), "field.resolution");
  for (std::size_t a = 0; a < 3; ++a)
    if (layout == GridLayout::node && res[a] < 2)
      r.fail(element("field.resolution", a),
             fmt::format("node layout needs at least 2 nodes per axis, got {}", res[a]));
  const std::int64_t nodes = std::int64_t{res[0]} * res[1] * res[2];
  if (nodes > kMaxGridNodes)
    r.fail("field.resolution", fmt::format("too many nodes: {} (at most {})", nodes, kMaxGridNodes));
  try {
    return make_grid(box, source, res, layout, interpolation);
  } catch (const std::invalid_argument& e) {
    r.fail("field.resolution", e.what());
  }
}

// [field] kind = "volume": the file's samples as a grid (lib/volume/volume_grid.h); a relative
// file is relative to the scene file's folder.  Errors of the volume file are its own line.
GridField read_volume_field(const Reader& r, const toml::table& t, const Box& box,
                            std::string_view source_name, std::string& files) {
  r.check_keys(t, "field", {"kind", "file", "value", "placement", "layout", "interpolation"});
  std::filesystem::path file(r.string(r.require(t, "file", "field"), "field.file"));
  if (file.empty()) r.fail("field.file", "empty");
  if (file.is_relative()) file = std::filesystem::path(source_name).parent_path() / file;
  VolumeMapping mapping;
  if (const toml::node* n = t.get("value"); n && n->is_table()) {
    const toml::table& w = *n->as_table();
    r.check_keys(w, "field.value", {"window"});
    const toml::array& a = r.array(r.require(w, "window", "field.value"), "field.value.window", 2);
    mapping = {VolumeValue::window, r.number(*a.get(0), "field.value.window[0]"),
               r.number(*a.get(1), "field.value.window[1]")};
    if (!(mapping.lo < mapping.hi) || !std::isfinite(mapping.hi - mapping.lo))
      r.fail("field.value.window", fmt::format("[{}, {}] needs lo < hi (and a finite width)", mapping.lo, mapping.hi));
  } else {
    // A window is a table ([window] above); the plain values by name.
    constexpr NameTable<VolumeValue, 2> named{{{VolumeValue::raw, "raw"}, {VolumeValue::rescale, "rescale"}}};
    mapping.kind = r.choice(t, "value", "field", named, mapping.kind);
  }
  const auto placement = r.choice(t, "placement", "field", kVolumePlacementNames, VolumePlacement::header);
  const auto layout = r.choice(t, "layout", "field", kGridLayoutNames, GridLayout::node);
  const auto interpolation = r.choice(t, "interpolation", "field", kInterpolationNames, Interpolation::trilinear);
  try {
    // The grid's node cap (as for kind = "grid") and the memory budget, checked from the header
    // before reading: the samples in their own type, and at the peak what the reader holds
    // beside them or the bits that put a header's permuted axes in world order.
    VolumeReadOptions options{std::int64_t{kMaxGridNodes} * 16, kMaxGridNodes, placement == VolumePlacement::header};
    if (r.volume_budget() > 0 && r.volume_budget() < static_cast<double>(options.max_bytes))
      options.max_bytes = static_cast<std::int64_t>(r.volume_budget());
    Volume v = read_volume(file, options);
    // The reader checked the samples; their 8/16-bit code table is built next, beside them.
    const double held = static_cast<double>(grid_nodes_bytes(v.type(), v.count()));
    if (r.volume_budget() > 0 && held > r.volume_budget())
      r.fail("field.file", fmt::format("{}: its samples and their table of values take {:.0f} bytes, more than the "
                                       "{:.0f} allowed (--max-memory)", file.string(), held, r.volume_budget()));
    files = files_digest(v.files);
    return volume_grid(std::move(v), mapping, placement, box, layout, interpolation, file);
  } catch (const VolumeFileError& e) {
    throw SceneFileError(e.what());
  } catch (const std::invalid_argument& e) {
    r.fail("field.file", fmt::format("{}: {}", file.string(), e.what()));
  }
}

// A volume placed by its header brings its own box: [volume] min and max would contradict it.
bool volume_places_itself(const Reader& r, const toml::table& field) {
  const toml::node* kind = field.get("kind");
  if (!kind || !kind->is_string() || kind->as_string()->get() != "volume") return false;
  return r.choice(field, "placement", "field", kVolumePlacementNames, VolumePlacement::header) ==
         VolumePlacement::header;
}

// What a grid kind's reader needs beside its table.
struct FieldContext {
  const Box& box;
  std::string_view source_name;  // the scene file: a volume's relative path is relative to its folder
  std::string& files;            // the digest of the files read (lib/scene_hash.h)
};

// The grid field kinds, each its name, its reader and the nodes its grid will hold as its table
// tells before anything is read (none where only the reading can tell: a volume's reader checks
// the file's header against the memory budget itself), once: a new grid kind is a row here.
struct GridKind {
  std::string_view name;
  GridField (*read)(const Reader& r, const toml::table& t, const FieldContext& context);
  std::optional<NodeCounts> (*nodes)(const toml::table& t);
};
constexpr GridKind kGridKinds[] = {
    {"grid", [](const Reader& r, const toml::table& t, const FieldContext& c) { return read_grid(r, t, c.box); },
     [](const toml::table& t) { return node_counts_at(t, "resolution"); }},
    {"volume",
     [](const Reader& r, const toml::table& t, const FieldContext& c) {
       return read_volume_field(r, t, c.box, c.source_name, c.files);
     },
     [](const toml::table&) -> std::optional<NodeCounts> { return std::nullopt; }},
};

const GridKind* grid_kind(std::string_view name) {
  for (const GridKind& k : kGridKinds)
    if (k.name == name) return &k;
  return nullptr;
}

[[noreturn]] void unknown_kind(const Reader& r, std::string_view path, std::string_view kind) {
  std::vector<std::string_view> known;
  for (const AnalyticKind& k : kAnalyticKinds) known.push_back(k.name);
  for (const GridKind& k : kGridKinds) known.push_back(k.name);
  const std::string_view last = known.back();
  known.pop_back();
  r.fail(child(path, "kind"),
         fmt::format("unknown field kind \"{}\" (expected {} or {})", kind, fmt::join(known, ", "), last));
}

Field read_field(const Reader& r, const toml::table& t, const Box& box, std::string_view source_name,
                 std::string& files) {
  const std::string_view kind = read_kind(r, t, "field");
  if (const AnalyticKind* k = analytic_kind(kind))
    return std::visit([](const auto& f) -> Field { return f; }, k->read(r, t, "field"));
  if (const GridKind* k = grid_kind(kind)) return k->read(r, t, FieldContext{box, source_name, files});
  unknown_kind(r, "field", kind);
}

// One curve of a pair, one per channel given (three for an RGB emission or colour); `partner` is
// the key that made this one required.
std::vector<PiecewiseLinear> read_curves(const Reader& r, const toml::table& t, std::string_view key,
                                         std::string_view partner) {
  const std::string path = child("transfer", key);
  const toml::node* n = t.get(key);
  if (!n) r.fail(path, fmt::format("missing ({} needs {})", partner, key));
  const bool channels = key == "emission" || key == "color";
  const std::vector<std::vector<ControlPoint>> curves = r.points(*n, path, channels ? 3 : 1);
  std::vector<PiecewiseLinear> out;
  for (std::size_t c = 0; c < curves.size(); ++c) {
    const std::vector<ControlPoint>& pts = curves[c];
    for (std::size_t i = 0; i < pts.size(); ++i) {
      // An RGB point's value is named by its place: transfer.emission[2][3] is point 2's blue.
      const std::string at = curves.size() == 1 ? element(path, i) : element(element(path, i), c + 1);
      if (pts[i].y < 0) r.fail(at, fmt::format("negative {} {}", key, pts[i].y));
      if (key == "opacity" && pts[i].y >= 1)
        r.fail(element(path, i), fmt::format("opacity {} must be below 1 (1 is opaque)", pts[i].y));
    }
    try {
      out.emplace_back(pts);
    } catch (const std::invalid_argument& e) {
      r.fail(path, e.what());
    }
  }
  return out;
}

// The transfer function of each channel: one for grey, three (red, green, blue) when the emission
// or colour points carry three values; the extinction or opacity is every channel's.
std::vector<TransferFunction> read_transfer(const Reader& r, const toml::table& t) {
  r.check_keys(t, "transfer", {"emission", "extinction", "opacity", "color", "unit_length"});
  const bool ee = t.contains("emission") || t.contains("extinction");
  if (ee)
    for (std::string_view key : {"opacity", "color", "unit_length"})
      if (t.contains(key))
        r.fail(child("transfer", key),
               "mixed conventions: use emission/extinction or opacity/color, not both");
  std::vector<TransferFunction> channels;
  try {
    if (ee) {  // locals, so that errors come in file order (argument order is unspecified)
      const std::vector<PiecewiseLinear> emission = read_curves(r, t, "emission", "extinction");
      const PiecewiseLinear extinction = read_curves(r, t, "extinction", "emission")[0];
      for (const PiecewiseLinear& g : emission) channels.push_back(TransferFunction::emission_extinction(g, extinction));
      return channels;
    }
    if (!t.contains("opacity") && !t.contains("color"))
      r.fail("transfer", "needs emission and extinction, or opacity and color");
    const PiecewiseLinear opacity = read_curves(r, t, "opacity", "color")[0];
    const std::vector<PiecewiseLinear> color = read_curves(r, t, "color", "opacity");
    const double unit_length = r.number_or(t, "unit_length", "transfer", 1.0);
    if (!(unit_length > 0))
      r.fail("transfer.unit_length", fmt::format("must be positive, got {}", unit_length));
    for (const PiecewiseLinear& c : color) channels.push_back(TransferFunction::opacity_color(opacity, c, unit_length));
    return channels;
  } catch (const std::invalid_argument& e) {
    r.fail("transfer", e.what());
  }
}

// One intensity for every channel, or (RGB scenes) color = [r, g, b].
std::vector<double> read_background(const Reader& r, const toml::table* t, int channels) {
  std::vector<double> b(channels, 0.0);
  if (!t) return b;
  r.check_keys(*t, "background", {"intensity", "color"});
  if (t->contains("intensity") && t->contains("color"))
    r.fail("background.color", "give intensity or color, not both");
  if (const toml::node* color = t->get("color")) {
    if (channels != 3)
      r.fail("background.color", "an RGB background needs an RGB transfer function ([value, r, g, b] points)");
    const Vec3 rgb = r.vec3(*color, "background.color");
    b.assign(rgb.data(), rgb.data() + 3);
  } else {
    b.assign(channels, r.number_or(*t, "intensity", "background", 0.0));
  }
  for (std::size_t c = 0; c < b.size(); ++c)
    if (b[c] < 0)
      r.fail(t->contains("color") ? element("background.color", c) : std::string("background.intensity"),
             fmt::format("negative intensity {}", b[c]));
  return b;
}

// [camera]: only the keys the projection uses; `rays` is the fan's name for `width`.
// [shading]: the Phong / Blinn-Phong factor on the emission (lib/shading.h); every key optional.
std::optional<Shading> read_shading(const Reader& r, const toml::table* t, const Field& field) {
  if (!t) return std::nullopt;
  r.check_keys(*t, "shading", {"model", "ambient", "diffuse", "specular", "shininess", "light", "normal", "two_sided"});
  Shading s;
  s.model = r.choice(*t, "model", "shading", kShadingModelNames, s.model);
  s.normal = r.choice(*t, "normal", "shading", kNormalSignNames, s.normal);
  s.ambient = r.number_or(*t, "ambient", "shading", s.ambient);
  s.diffuse = r.number_or(*t, "diffuse", "shading", s.diffuse);
  s.specular = r.number_or(*t, "specular", "shading", s.specular);
  s.shininess = r.number_or(*t, "shininess", "shading", s.shininess);
  if (const toml::node* n = t->get("light")) {
    if (n->is_string()) {
      if (r.string(*n, "shading.light") != "headlight")
        r.fail("shading.light", fmt::format("unknown value \"{}\" (expected \"headlight\" or [x, y, z] toward the light)",
                                            r.string(*n, "shading.light")));
    } else {
      s.light = r.vec3(*n, "shading.light");
    }
  }
  if (const toml::node* n = t->get("two_sided")) {
    if (!n->is_boolean()) r.fail("shading.two_sided", fmt::format("expected true or false, got {}", type_name(*n)));
    s.two_sided = **n->as_boolean();
  }
  try {
    validate(s);
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    const auto colon = what.find(": ");
    r.fail(what.substr(0, colon), what.substr(colon + 2));
  }
  if (const auto* grid = std::get_if<GridField>(&field); grid && grid->interpolation() == Interpolation::nearest)
    r.fail("shading", "a nearest-interpolated grid has no gradient to shade with (use interpolation = \"trilinear\")");
  return s;
}

std::optional<Camera> read_camera(const Reader& r, const toml::table* t) {
  if (!t) return std::nullopt;
  Camera c;
  c.projection = r.choice(*t, "projection", "camera", kProjectionNames, c.projection);
  std::vector<std::string_view> allowed{"projection", "eye"};
  switch (c.projection) {
    case Projection::perspective: allowed.insert(allowed.end(), {"target", "up", "fov", "width", "height"}); break;
    case Projection::orthographic: allowed.insert(allowed.end(), {"target", "up", "extent", "width", "height"}); break;
    case Projection::fan: allowed.insert(allowed.end(), {"angle", "fov", "rays", "width", "height"}); break;
  }
  constexpr std::string_view all[] = {"projection", "eye", "target", "up", "fov", "extent",
                                      "width", "height", "angle", "rays"};
  for (const auto& [key, value] : *t) {
    if (std::find(allowed.begin(), allowed.end(), key.str()) != allowed.end()) continue;
    const bool known = std::find(std::begin(all), std::end(all), key.str()) != std::end(all);
    r.fail(child("camera", key.str()),
           fmt::format("{} (a {} camera takes: {})",
                       known ? fmt::format("does not apply to a {} camera", to_string(c.projection))
                             : std::string("unknown key"),
                       to_string(c.projection), fmt::join(allowed, ", ")));
  }
  if (const toml::node* n = t->get("eye")) c.eye = r.vec3(*n, "camera.eye");
  if (const toml::node* n = t->get("target")) c.target = r.vec3(*n, "camera.target");
  if (const toml::node* n = t->get("up")) c.up = r.vec3(*n, "camera.up");
  c.fov_degrees = r.number_or(*t, "fov", "camera", c.fov_degrees);
  c.extent = r.number_or(*t, "extent", "camera", c.extent);
  c.angle_degrees = r.number_or(*t, "angle", "camera", c.angle_degrees);
  if (t->contains("rays") && t->contains("width"))
    r.fail("camera.rays", "give rays or width, not both (rays is the fan's name for width)");
  if (c.projection == Projection::fan) c.height = 1;
  for (std::string_view key : {"width", "rays", "height"}) {
    const toml::node* n = t->get(key);
    if (!n) continue;
    const std::string path = child("camera", key);
    const int v = r.count(*n, path);
    if (v > kMaxImageSide) r.fail(path, fmt::format("too large, got {} (at most {})", v, kMaxImageSide));
    (key == "height" ? c.height : c.width) = v;
  }
  try {
    validate(c);
  } catch (const CameraError& e) {
    // A fan's width may have been given as rays.  A string, not a view: the conditional makes a
    // temporary std::string, which a view would outlive (AddressSanitizer: stack use after scope).
    const std::string key = e.field() == "width" && t->contains("rays") ? "rays" : e.field();
    r.fail(child("camera", key), e.reason());
  }
  return c;
}

// toml++ recurses once per key nesting level and overflows the stack on a dotted key of tens
// of thousands of parts, so long dotted runs are rejected before parsing.  Dots in strings and
// comments do not nest; ',', '=', brackets, braces and line ends end a run.  With inline
// tables capped at 256 levels by toml++, this bounds the nesting to about 8500 levels.
constexpr int kMaxDotsPerRun = 32;

// Index of the last character of the string that opens at text[i] (a line end closes an
// unterminated single-line string; the parser reports that).
std::size_t string_end(std::string_view text, std::size_t i) {
  const char q = text[i];
  const bool multi = text.substr(i, 3) == std::string(3, q);
  for (std::size_t j = i + (multi ? 3 : 1); j < text.size(); ++j) {
    if (q == '"' && text[j] == '\\') {
      ++j;
    } else if (!multi && text[j] == '\n') {
      return j - 1;
    } else if (text[j] == q) {
      if (!multi) return j;
      std::size_t k = 1;  // up to two quotes may precede the closing three
      while (j + k < text.size() && text[j + k] == q) ++k;
      if (k >= 3) return j + k - 1;
      j += k - 1;
    }
  }
  return text.size() - 1;
}

// Index of the first dot beyond kMaxDotsPerRun in one dotted run outside strings and comments.
std::optional<std::size_t> overlong_dotted_key(std::string_view text) {
  int dots = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '"' || c == '\'') {
      i = string_end(text, i);
    } else if (c == '#') {
      i = std::min(text.find('\n', i), text.size()) - 1;  // the line end resets the run
    } else if (c == '.') {
      if (++dots > kMaxDotsPerRun) return i;
    } else if (std::string_view(",=[]{}\n").find(c) != std::string_view::npos) {
      dots = 0;
    }
  }
  return std::nullopt;
}

}  // namespace

std::optional<std::string> toml_nesting_problem(std::string_view text) {
  const auto at = overlong_dotted_key(text);
  if (!at) return std::nullopt;
  const auto line = 1 + std::count(text.begin(), text.begin() + *at, '\n');
  const auto column = *at - (text.rfind('\n', *at) + 1) + 1;  // npos + 1 wraps to 0
  return fmt::format("line {}, column {}: key nested too deeply (more than {} dots)", line, column,
                     kMaxDotsPerRun);
}

namespace {

toml::table parse_toml(const Reader& r, std::string_view text, std::string_view source_name) {
  if (const auto problem = toml_nesting_problem(text)) r.fail("(syntax)", *problem);
  try {
    return toml::parse(text, source_name);
  } catch (const toml::parse_error& e) {
    const auto& at = e.source().begin;
    r.fail("(syntax)", fmt::format("line {}, column {}: {}", at.line, at.column, e.description()));
  }
}

}  // namespace

double grid_bytes(const NodeCounts& nodes) {
  return static_cast<double>(nodes[0]) * static_cast<double>(nodes[1]) * static_cast<double>(nodes[2]) *
         sizeof(double);
}

std::optional<NodeCounts> node_counts_at(const toml::table& t, std::string_view key) {
  const toml::array* a = t.get_as<toml::array>(key);
  if (!a || a->size() != 3) return std::nullopt;
  NodeCounts n{};
  for (std::size_t i = 0; i < 3; ++i) {
    // Whole numbers below 2^53 (any node count a machine could hold), so the cast is exact.
    const auto v = a->get(i)->value<double>();
    if (!v || !(*v >= 1 && *v <= 0x1p53) || *v != std::floor(*v)) return std::nullopt;
    n[i] = static_cast<std::int64_t>(*v);
  }
  return n;
}

std::optional<NodeCounts> field_grid_nodes(const toml::table& field) {
  const auto* kind = field.get_as<std::string>("kind");
  if (!kind) return std::nullopt;
  const GridKind* k = grid_kind(kind->get());
  return k ? k->nodes(field) : std::nullopt;
}

Scene parse_scene(std::string_view toml_text, std::string_view source_name) {
  return parse_scene(toml_text, source_name, 0);
}

Scene parse_scene(std::string_view toml_text, std::string_view source_name, double max_volume_bytes) {
  const Reader r(source_name, max_volume_bytes);
  const toml::table doc = parse_toml(r, toml_text, source_name);
  // Unknown keys first, so that a typo is reported as such and not as a missing key.
  r.check_keys(doc, "", {"volume", "field", "transfer", "background", "camera", "mode", "shading"});
  // mode = "xray" | "mip" | ...: the default of the commands' --mode (lib/scene_mode.h).
  if (const toml::node* mode = doc.get("mode"); mode && !parse_projection_mode(r.string(*mode, "mode")))
    r.fail("mode", fmt::format("unknown value \"{}\" (expected {})", r.string(*mode, "mode"), projection_mode_list()));
  const toml::node* field = doc.get("field");
  const bool own_box = field && field->is_table() && volume_places_itself(r, *field->as_table());
  const toml::table empty;
  const toml::table& volume = own_box && !doc.contains("volume") ? empty : r.table(r.require(doc, "volume", ""), "volume");
  r.check_keys(volume, "volume", {"min", "max", "dims"});

  Scene scene;
  if (own_box) {
    for (std::string_view key : {"min", "max"})
      if (volume.contains(key))
        r.fail(child("volume", key), "not with a volume placed by its header (field.placement = \"header\"): "
                                     "the box is the file's; placement = \"box\" fills a stated box");
  } else {
    scene.box = read_box(r, volume);
  }
  const toml::node* dims = volume.get("dims");
  if (dims) scene.dims = r.int3(*dims, "volume.dims");
  scene.field = read_field(r, r.table(r.require(doc, "field", ""), "field"), scene.box, source_name,
                           scene.field_files);
  if (const auto* grid = std::get_if<GridField>(&scene.field); grid && !dims)
    scene.dims = grid->resolution();
  if (own_box) scene.box = std::get<GridField>(scene.field).box();
  const std::vector<TransferFunction> transfer = read_transfer(r, r.table(r.require(doc, "transfer", ""), "transfer"));
  const std::vector<double> background =
      read_background(r, r.optional_table(doc, "background", ""), static_cast<int>(transfer.size()));
  scene.transfer = transfer[0];
  scene.background = background[0];
  if (transfer.size() == 3) scene.color = ColorChannels{{transfer[0], transfer[1], transfer[2]}, {background[0], background[1], background[2]}};
  scene.camera = read_camera(r, r.optional_table(doc, "camera", ""));
  scene.shading = read_shading(r, r.optional_table(doc, "shading", ""), scene.field);
  return scene;
}

std::string read_scene_text(const std::filesystem::path& path) {
  const std::string name = path.string();
  const Reader r(name);
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) r.fail("(file)", "is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) r.fail("(file)", fmt::format("cannot open: {}", std::strerror(errno)));
  // Read in chunks with a cap, so that a device such as /dev/zero cannot hang the loader.
  std::string text;
  char buffer[1 << 16];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    text.append(buffer, static_cast<std::size_t>(in.gcount()));
    if (text.size() > kMaxFileBytes)
      r.fail("(file)", fmt::format("larger than {} bytes", kMaxFileBytes));
  }
  if (in.bad()) r.fail("(file)", "read error");
  return text;
}

Scene load_scene(const std::filesystem::path& path) { return parse_scene(read_scene_text(path), path.string()); }

Scene load_scene(const std::filesystem::path& path, double max_volume_bytes) {
  return parse_scene(read_scene_text(path), path.string(), max_volume_bytes);
}

std::string scene_toml(std::string_view toml_text, std::string_view source_name, double max_volume_bytes) {
  parse_scene(toml_text, source_name, max_volume_bytes);  // a scene first: its errors, not the printer's
  std::ostringstream out;
  out << toml::toml_formatter(parse_toml(Reader(source_name), toml_text, source_name)) << '\n';
  return out.str();
}

std::string exported_scene_toml(std::string_view toml_text, std::string_view source_name,
                                const std::optional<std::array<int, 3>>& grid_nodes,
                                const std::optional<OpacityColourPoints>& transfer) {
  parse_scene(toml_text, source_name);
  toml::table doc = parse_toml(Reader(source_name), toml_text, source_name);
  if (grid_nodes) {
    // The analytic field becomes the source of a grid whose nodes are the ones exported: node
    // layout (on the box faces) and trilinear, as the export's files are read.
    toml::table source = *doc["field"].as_table();
    toml::table field{{"kind", "grid"},
                      {"resolution", toml::array{(*grid_nodes)[0], (*grid_nodes)[1], (*grid_nodes)[2]}},
                      {"layout", "node"},
                      {"interpolation", "trilinear"}};
    field.insert("source", std::move(source));
    doc.insert_or_assign("field", std::move(field));
  }
  if (transfer) {
    toml::array opacity, color;
    for (const ControlPoint& p : transfer->opacity) opacity.push_back(toml::array{p.v, p.y});
    for (const std::vector<double>& p : transfer->color) {
      toml::array point;
      for (double x : p) point.push_back(x);
      color.push_back(std::move(point));
    }
    doc.insert_or_assign("transfer", toml::table{{"opacity", std::move(opacity)},
                                                 {"color", std::move(color)},
                                                 {"unit_length", transfer->unit_length}});
  }
  std::ostringstream out;
  out << toml::toml_formatter(doc) << '\n';
  return out.str();
}

std::string_view default_scene_toml() { return kDefaultScene; }

Scene default_scene() { return parse_scene(default_scene_toml(), "<default scene>"); }

}  // namespace vrv
