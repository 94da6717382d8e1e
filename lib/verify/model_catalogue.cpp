#include "lib/verify/model_catalogue.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include <fmt/format.h>

namespace vrv {
namespace {

bool opacity_color(const Scene& scene) { return scene.transfer.convention() == Convention::opacity_color; }

std::string rule_opacity(SegmentRule rule, const Scene& scene) {
  switch (rule) {
    case SegmentRule::riemann: return "extinction exp(-tau h) per sample";
    case SegmentRule::alpha:
      return opacity_color(scene) ? "opacity taken per sample (not corrected to the sample distance)"
                                  : "opacity 1 - exp(-tau h) for the sample distance";
    case SegmentRule::trapezoid: return "trapezoid in tau and g e^-Phi between samples";
    default: return "exact for g, tau linear between samples (pre-integration)";
  }
}

// The alpha rule on an opacity/colour transfer function takes the opacity per sample as given.
bool rule_corrects_opacity(SegmentRule rule, const Scene& scene) {
  return !(rule == SegmentRule::alpha && opacity_color(scene));
}

constexpr std::pair<Strategy, const char*> kPlacements[] = {
    {Strategy::step, "step (first sample half a step in)"},
    {Strategy::vtk, "vtk (first sample one step in, last partial step dropped)"},
    {Strategy::inviwo, "inviwo (step rounded to fit, samples at midpoints)"},
    {Strategy::partial, "partial (midpoints of whole steps, the last partial step at its own midpoint)"},
    {Strategy::exit_anchored, "exit_anchored (midpoints of whole steps back from the exit, the partial "
                              "step at the entry at its own midpoint)"}};

}  // namespace

std::span<const std::pair<Strategy, const char*>> diagnosis_placements() { return kPlacements; }

namespace {

std::string_view placement_text(Strategy s) {
  for (auto [strategy, text] : kPlacements)
    if (strategy == s) return text;
  return strategy_name(s);
}

// The default offsets of central differences (one voxel per axis, gradient_scheme.h).
Vec3 default_offsets(const Scene& scene) {
  return central_offsets(std::nullopt, std::get_if<GridField>(&scene.field), scene.box, scene.dims);
}
// Their smallest: the scale of the other offsets tried (one number, as --gradient-offset takes).
double default_offset(const Scene& scene) { return default_offsets(scene).minCoeff(); }

// A shaded model's gradient, as the report's short text and as words.
std::pair<std::string, std::string> gradient_words(const DiscreteConfig& c, const Scene& scene) {
  switch (c.gradient) {
    case GradientScheme::analytic: return {"analytic", "the field's exact gradient"};
    case GradientScheme::nodes:
      return {"nodes", "gradients by central differences at the grid's nodes, interpolated (Lee & Newman)"};
    default:
      if (c.gradient_offset)
        return {fmt::format("central {:g}", *c.gradient_offset),
                fmt::format("gradients by central differences at the sample, offset {:g}", *c.gradient_offset)};
      const Vec3 h = default_offsets(scene);
      return {"central", h.minCoeff() == h.maxCoeff()
                             ? fmt::format("gradients by central differences at the sample, offset one voxel ({:g})", h[0])
                             : fmt::format("gradients by central differences at the sample, offset one voxel per "
                                           "axis ({:g}, {:g}, {:g})", h[0], h[1], h[2])};
  }
}

Candidate label(const DiscreteConfig& base, const std::string& opacity, bool opacity_corrected) {
  Candidate l;
  l.placement = std::string(strategy_name(base.sampling.strategy));
  l.rule = std::string(segment_rule_name(base.rule));
  l.opacity = opacity;
  l.opacity_corrected = opacity_corrected;
  l.name = fmt::format("{} placement, {} rule, {}", placement_text(base.sampling.strategy), l.rule, opacity);
  if (base.color == ColorConvention::premultiplied) {
    l.color = "premultiplied";
    l.name += ", colour premultiplied by the opacity per unit distance";
  }
  if (base.table_size > 0) {
    const bool centred = base.table_lookup == TableLookup::centred;
    l.table = fmt::format("{} {}", base.table_size, table_lookup_name(base.table_lookup));
    l.name += fmt::format(", transfer function read from {}-entry tables {}", base.table_size,
                          centred ? "at their entries (half-texel centred)"
                                  : "as a plain texture coordinate (no half-texel remap)");
  }
  return l;
}

// label() with a shaded scene's gradient scheme.
Candidate scene_label(const DiscreteConfig& base, const Scene& scene, const std::string& opacity,
                      bool opacity_corrected) {
  Candidate l = label(base, opacity, opacity_corrected);
  if (scene.shading) {
    auto [gradient, words] = gradient_words(base, scene);
    l.gradient = std::move(gradient);
    l.gradient_choice = GradientChoice{base.gradient, base.gradient_offset};
    l.name += ", " + words;
  }
  return l;
}

// `base` at every step, labelled from its own settings; `opacity` describes its opacity.
Model model(const Scene& scene, const std::vector<double>& steps, const DiscreteConfig& base,
            const std::string& opacity, bool opacity_corrected = true) {
  Model m{scene_label(base, scene, opacity, opacity_corrected), {}};
  for (double h : steps) {
    DiscreteConfig c = base;
    c.sampling.step = h;
    c.sampling.dims = scene.dims;
    m.per_step.push_back(c);
  }
  return m;
}

DiscreteConfig placed(Strategy strategy, SegmentRule rule) {
  DiscreteConfig c;
  c.rule = rule;
  c.sampling.strategy = strategy;
  return c;
}

// The opacity for a unit distance L used at every sample, whatever the sample distance h: vrv's
// oversampling without correction (N = L / h samples per unit step, centred so that they sit
// where a plain step-h raycast puts them).  Nothing when some L / h is not whole.
std::optional<Model> uncorrected_unit_model(const Scene& scene, const std::vector<double>& steps,
                                            Strategy strategy, double L) {
  Model m = model(scene, steps, placed(strategy, SegmentRule::alpha),
                  fmt::format("opacity 1 - exp(-tau L) for the unit distance L = {:g}, not corrected "
                              "to the sample distance", L),
                  false);
  for (std::size_t k = 0; k < steps.size(); ++k) {
    const double N = L / steps[k];
    if (std::abs(N - std::round(N)) > 1e-9 * N || std::round(N) < 1 || N > 65536) return std::nullopt;
    DiscreteConfig& c = m.per_step[k];
    c.sampling.step = L;
    c.oversample = static_cast<int>(std::round(N));
    c.centred_oversamples = c.oversample > 1;
  }
  return m;
}

void add_placements_and_rules(const Scene& scene, const std::vector<double>& steps, std::vector<Model>& out) {
  for (auto [strategy, text] : kPlacements)
    for (SegmentRule rule : {SegmentRule::riemann, SegmentRule::alpha, SegmentRule::trapezoid,
                             SegmentRule::exact_linear})
      out.push_back(model(scene, steps, placed(strategy, rule), rule_opacity(rule, scene),
                          rule_corrects_opacity(rule, scene)));
}

// The corrected alpha rule at every placement, with straight and premultiplied colour.
void add_opacity_per_unit_distance(const Scene& scene, const std::vector<double>& steps, DiscreteConfig corrected,
                                   const std::string& text, std::vector<Model>& out) {
  for (auto [strategy, name] : kPlacements) {
    corrected.sampling.strategy = strategy;
    out.push_back(model(scene, steps, corrected, text));
    DiscreteConfig premultiplied = corrected;
    premultiplied.color = ColorConvention::premultiplied;
    out.push_back(model(scene, steps, premultiplied, text));
  }
}

void add_tables(const Scene& scene, const std::vector<double>& steps, const DiscreteConfig& corrected,
                const std::string& text, const std::vector<int>& sizes, std::vector<Model>& out) {
  for (int size : sizes)
    for (TableLookup lookup : {TableLookup::centred, TableLookup::uncentred})
      for (auto [strategy, name] : kPlacements) {
        DiscreteConfig c = corrected;
        c.sampling.strategy = strategy;
        c.table_size = size;
        c.table_lookup = lookup;
        out.push_back(model(scene, steps, c, text));
      }
}

}  // namespace

std::vector<Model> model_catalogue(const Scene& scene, const std::vector<double>& steps, const VerifyOptions& opt) {
  std::vector<Model> out;
  add_placements_and_rules(scene, steps, out);
  // The alpha rule as renderers correct it: for emission/extinction that is its own convention.
  DiscreteConfig corrected = placed(Strategy::step, SegmentRule::alpha);
  std::string corrected_text = rule_opacity(SegmentRule::alpha, scene);
  if (opacity_color(scene)) {
    corrected.opacity_unit = OpacityUnit::per_unit_distance;
    corrected_text = fmt::format("opacity per unit distance L = {:g} corrected to the sample distance, "
                                 "1 - (1 - a)^(h/L)", scene.transfer.unit_length());
    add_opacity_per_unit_distance(scene, steps, corrected, corrected_text, out);
  }
  add_tables(scene, steps, corrected, corrected_text, opt.table_sizes, out);
  if (!opacity_color(scene)) {
    const double L = opt.unit_distance > 0 ? opt.unit_distance : *std::max_element(steps.begin(), steps.end());
    for (Strategy strategy : {Strategy::step, Strategy::inviwo})
      if (auto m = uncorrected_unit_model(scene, steps, strategy, L)) out.push_back(std::move(*m));
  }
  return out;
}

std::vector<GradientChoice> gradient_choices(const Scene& scene) {
  if (!scene.shading) return {};
  // The default first: ties (nothing separates the schemes) keep it.
  std::vector<GradientChoice> out{{GradientScheme::central, std::nullopt},
                                  {GradientScheme::analytic, std::nullopt},
                                  {GradientScheme::central, 0.5 * default_offset(scene)},
                                  {GradientScheme::central, 2 * default_offset(scene)}};
  if (std::holds_alternative<GridField>(scene.field)) out.push_back({GradientScheme::nodes, std::nullopt});
  return out;
}

Model with_gradient(const Model& model, const GradientChoice& gradient, const Scene& scene) {
  Model m = model;
  for (DiscreteConfig& c : m.per_step) c.gradient = gradient.scheme, c.gradient_offset = gradient.offset;
  m.label = scene_label(m.per_step.back(), scene, model.label.opacity, model.label.opacity_corrected);
  return m;
}

std::vector<Model> gradient_variants(const Model& nearest, const Scene& scene) {
  std::vector<Model> out;
  for (const GradientChoice& g : gradient_choices(scene)) out.push_back(with_gradient(nearest, g, scene));
  return out;
}

namespace {

// Whether a centred N-entry table reproduces the transfer function (to rounding): every
// breakpoint of its curves sits on an entry, and it has no jump a table cannot hold.
bool table_holds_breakpoints(const TransferFunction& tf, int n) {
  const std::vector<double>& b = tf.breakpoints();
  if (b.size() < 2 || !(b.back() > b.front())) return false;
  for (double v : b) {
    const auto jump = tf.jump_at(v);
    if (jump.emission != 0 || jump.extinction != 0) return false;
    const double x = (v - b.front()) / (b.back() - b.front()) * (n - 1);
    if (std::abs(x - std::round(x)) > 1e-9 * n) return false;
  }
  return true;
}

}  // namespace

std::string configuration_key(DiscreteConfig c, const Scene& scene) {
  if (c.table_size > 0 && c.table_lookup == TableLookup::centred && table_holds_breakpoints(scene.transfer, c.table_size))
    c.table_size = 0;
  if (c.table_size == 0) c.table_lookup = TableLookup::centred;  // read only with a table
  const SamplingConfig& s = c.sampling;
  const auto optional = [](const std::optional<double>& v) { return v ? fmt::format("{:a}", *v) : "-"; };
  return fmt::format("rule {} strategy {} rate {:a} step {:a} dims {} {} {} eye {} oversample {} centred {} "
                     "correction {} termination {} skip {} compositing {} classification {} precision {} "
                     "opacity {} color {} table {} {} gradient {} {} shade {}",
                     static_cast<int>(c.rule), static_cast<int>(s.strategy), s.rate, s.step, s.dims[0], s.dims[1],
                     s.dims[2], s.eye ? fmt::format("{:a} {:a} {:a}", (*s.eye)[0], (*s.eye)[1], (*s.eye)[2]) : "-",
                     c.oversample, c.centred_oversamples, static_cast<int>(c.correction), optional(c.termination),
                     optional(c.skip_below), static_cast<int>(c.compositing), static_cast<int>(c.classification),
                     static_cast<int>(c.precision), static_cast<int>(c.opacity_unit), static_cast<int>(c.color),
                     c.table_size, static_cast<int>(c.table_lookup), static_cast<int>(c.gradient),
                     optional(c.gradient_offset), static_cast<int>(c.shade_at));
}

bool same_model(const Model& a, const Model& b, const Scene& scene) {
  if (a.per_step.size() != b.per_step.size()) return false;
  for (std::size_t k = 0; k < a.per_step.size(); ++k)
    if (configuration_key(a.per_step[k], scene) != configuration_key(b.per_step[k], scene)) return false;
  return true;
}

}  // namespace vrv
