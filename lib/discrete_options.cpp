#include "lib/discrete_options.h"

#include <algorithm>
#include <array>
#include <stdexcept>

#include <fmt/format.h>

namespace vrv {
namespace {

using O = DiscreteOptions;

// The declarations, in the command line's help order.  Defaults are DiscreteOptions' initializers.
const std::array<DiscreteOptionField, 20> kFields{{
    {Option::method, &O::method,
     "Discrete raycast: riemann | alpha | trapezoid | exact_linear | moreland "
     "(omit for the reference integrator; the options below need it)",
     false},
    {Option::strategy, &O::strategy,
     "Sample placement: eye | entry | entry_exit | entry_exit_corner (default) | step | vtk | inviwo | "
     "partial | exit_anchored"},
    {Option::rate, &O::rate, "Samples per voxel (eye, entry, entry_exit, entry_exit_corner; default 1)"},
    {Option::step, &O::step,
     "World step H (step, vtk, inviwo, partial, exit_anchored; --step alone implies --strategy step)"},
    {Option::oversample, &O::oversample, "Oversampling factor N dividing the unit step"},
    {Option::centred_oversamples, &O::centred_oversamples,
     "Put the N oversamples at the centres of the unit step's N parts (default: from the unit sample on)"},
    {Option::correction, &O::correction,
     "Opacity correction (alpha method): none | lacroute | schulze | lee_newman | lee_newman_quadratic"},
    {Option::termination, &O::termination, "Early ray termination at this accumulated opacity (off by default)"},
    {Option::skip, &O::skip, "Skip samples whose opacity is below this (off by default)"},
    {Option::compositing, &O::compositing, "front_to_back | back_to_front"},
    {Option::classification, &O::classification, "post | pre (grid fields)"},
    {Option::precision, &O::precision, "double | float"},
    {Option::opacity_unit, &O::opacity_unit,
     "Alpha rule, opacity/colour scenes: sample (opacity per sample, unit_length unused) | "
     "distance (per unit_length, corrected to the step: 1 - (1 - a)^(H/L))"},
    {Option::color, &O::color,
     "Alpha rule: straight (emit colour * alpha) | premultiplied (colour stored times the "
     "transfer function's opacity, emitted as stored)"},
    {Option::table_size, &O::table_size,
     "Read the transfer function from N-entry tables over its control-point range (0: no table)"},
    {Option::table_lookup, &O::table_lookup,
     "centred (entry i read at its own value; half-texel remap) | uncentred (plain texture coordinate)"},
    {Option::gradient, &O::gradient,
     "Shaded scenes ([shading]): the gradient the samples shade with: analytic (the field's exact "
     "gradient) | central (differences at the sample) | nodes (differences at a grid's nodes, "
     "interpolated; Lee & Newman)"},
    {Option::gradient_offset, &O::gradient_offset,
     "The central differences' offset (world length; default one node spacing, or one voxel of volume.dims)"},
    {Option::shade_at, &O::shade_at,
     "Shaded scenes: samples (shade each sample) | nodes (shade each grid node's classified colour "
     "with its node gradient, then interpolate; needs --classification pre --gradient nodes)"},
    {Option::max_work, &O::max_work,
     "Refuse runs estimated above this many field evaluations: samples of --method, or the "
     "reference's (counted before casting)",
     false},
}};

template <class T, class Parse>
T parse_choice(const std::string& text, Option option, Parse&& parse, const std::string& choices) {
  const auto value = parse(text);
  if (!value) throw OptionError(option, fmt::format("unknown value '{}' (one of {})", text, choices));
  return *value;
}

// The first option given (in the table's order) that `refused` picks, or none.
template <class Refused>
std::optional<Option> first_given(const DiscreteOptions& opt, Refused&& refused) {
  for (const DiscreteOptionField& f : kFields)
    if (opt.was_given(f.option) && refused(f.option)) return f.option;
  return std::nullopt;
}

// The renderer conventions of DiscreteConfig (defaults documented there).
void set_conventions(const DiscreteOptions& opt, DiscreteConfig& c) {
  c.opacity_unit = parse_choice<OpacityUnit>(opt.opacity_unit, Option::opacity_unit, parse_opacity_unit, opacity_unit_list());
  c.color = parse_choice<ColorConvention>(opt.color, Option::color, parse_color_convention, color_convention_list());
  c.table_size = opt.table_size;
  c.table_lookup = parse_choice<TableLookup>(opt.table_lookup, Option::table_lookup, parse_table_lookup, table_lookup_list());
  c.gradient = parse_choice<GradientScheme>(opt.gradient, Option::gradient, parse_gradient_scheme, gradient_scheme_list());
  c.gradient_offset = opt.gradient_offset;
  c.shade_at = parse_choice<ShadeAt>(opt.shade_at, Option::shade_at, parse_shade_at, shade_at_list());
}

// Options that would be accepted and change nothing: refused, so that nobody believes they acted.
// (Premultiplied colour is not among them: it changes nothing only where the alpha rule's opacity
// is the stored one, which depends on the correction, oversampling, opacity unit and classification.)
void refuse_without_effect(const DiscreteConfig& c) {
  if (c.centred_oversamples && c.oversample == 1)
    throw OptionError(Option::centred_oversamples, "needs {0} N > 1 (one sample a step is the unit sample itself)",
                      {Option::oversample});
}

}  // namespace

void DiscreteOptions::give(Option option, std::string text) {
  for (auto& [o, t] : given)
    if (o == option) {
      t = std::move(text);
      return;
    }
  given.emplace_back(option, std::move(text));
}

bool DiscreteOptions::was_given(Option option) const { return given_text(option) != nullptr; }

const std::string* DiscreteOptions::given_text(Option option) const {
  for (const auto& [o, t] : given)
    if (o == option) return &t;
  return nullptr;
}

std::span<const DiscreteOptionField> discrete_option_fields() { return kFields; }

const DiscreteOptionField* discrete_option_field(Option option) {
  for (const DiscreteOptionField& f : kFields)
    if (f.option == option) return &f;
  return nullptr;
}

SamplingConfig sampling_config(const DiscreteOptions& opt, const Scene& scene) {
  SamplingConfig c;
  const std::string strategy = opt.strategy.value_or(opt.step ? "step" : "entry_exit_corner");
  c.strategy = parse_choice<Strategy>(strategy, Option::strategy, parse_strategy, strategy_list());
  const bool step_based = vrv::step_based(c.strategy);
  if (step_based && !opt.step)
    throw OptionError(Option::step, fmt::format("strategy {} needs {{0}} H", strategy), {Option::step});
  if (!step_based && opt.step)
    throw OptionError(Option::step, fmt::format("strategy {} takes {{0}}, not {{1}}", strategy),
                      {Option::rate, Option::step});
  if (step_based && opt.rate)
    throw OptionError(Option::rate, "a step-based strategy takes {0}, not {1}", {Option::step, Option::rate});
  c.rate = opt.rate.value_or(1.0);
  c.step = opt.step.value_or(0.0);
  c.dims = scene.dims;
  check_sampling(c);
  return c;
}

void check_max_work(const DiscreteOptions& opt) {
  if (!(opt.max_work > 0)) throw OptionError(Option::max_work, fmt::format("must be positive, got {}", opt.max_work));
}

std::optional<DiscreteConfig> discrete_config(const DiscreteOptions& opt, const Scene& scene) {
  check_max_work(opt);
  if (opt.method.empty()) {
    if (const auto o = first_given(opt, [](Option) { return true; }))
      throw OptionError(*o, "applies to a discrete raycast only; add {0} (the reference ignores it)", {Option::method});
    return std::nullopt;
  }
  DiscreteConfig c;
  c.rule = parse_choice<SegmentRule>(opt.method, Option::method, parse_segment_rule, segment_rule_list());
  c.sampling = sampling_config(opt, scene);
  c.oversample = opt.oversample;
  c.centred_oversamples = opt.centred_oversamples;
  c.correction = parse_choice<Correction>(opt.correction, Option::correction, parse_correction, correction_list());
  c.termination = opt.termination;
  c.skip_below = opt.skip;
  c.compositing = parse_choice<Compositing>(opt.compositing, Option::compositing, parse_compositing, compositing_list());
  c.classification =
      parse_choice<Classification>(opt.classification, Option::classification, parse_classification, classification_list());
  c.precision = parse_choice<Precision>(opt.precision, Option::precision, parse_precision, precision_list());
  set_conventions(opt, c);
  if (!scene.shading)
    if (const auto o = first_given(opt, [](Option o) {
          return o == Option::gradient || o == Option::gradient_offset || o == Option::shade_at;
        }))
      throw OptionError(*o, "applies to a shaded scene only (one with a [shading] table)");
  validate(c, std::holds_alternative<GridField>(scene.field), scene.transfer);
  refuse_without_effect(c);
  return c;
}

double diagonal_work(const std::optional<DiscreteConfig>& config, double tol, const Scene& scene) {
  return config ? discrete_samples(*config, scene) : reference_evaluations(scene, tol);
}

void refuse_work(const DiscreteOptions& opt, bool discrete, double work, long rays) {
  std::string asked;
  for (const Option o : {Option::rate, Option::step, Option::oversample})
    if (const std::string* text = opt.given_text(o))
      asked += fmt::format("{}{} {}", asked.empty() ? "" : ", ", option_name(o, Spelling::flag), *text);
  throw std::invalid_argument(fmt::format(
      "{}: about {:.3g} {} on {} ray{}, above the work limit of {:.3g}; {} or allow it with --max-work {}",
      asked.empty() ? std::string("--max-work") : asked, work,
      discrete ? "samples" : "field evaluations of the reference", rays, rays == 1 ? "" : "s", opt.max_work,
      discrete ? "coarsen the sampling" : "loosen --tol, make the image smaller, simplify the field",
      work_limit_allowing(work)));
}

}  // namespace vrv
