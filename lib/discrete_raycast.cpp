#include "lib/discrete_raycast.h"

#include <stdexcept>

#include <fmt/format.h>

#include "lib/option_error.h"
#include "lib/util/enum_names.h"

namespace vrv {
namespace {

constexpr NameTable<OpacityUnit, 2> kOpacityUnits{
    {{OpacityUnit::per_sample, "sample"}, {OpacityUnit::per_unit_distance, "distance"}}};
static_assert(names_complete(kOpacityUnits));
constexpr NameTable<ColorConvention, 2> kColors{
    {{ColorConvention::straight, "straight"}, {ColorConvention::premultiplied, "premultiplied"}}};
static_assert(names_complete(kColors));
constexpr NameTable<Compositing, 2> kCompositing{
    {{Compositing::front_to_back, "front_to_back"}, {Compositing::back_to_front, "back_to_front"}}};
static_assert(names_complete(kCompositing));
constexpr NameTable<Classification, 2> kClassification{{{Classification::post, "post"}, {Classification::pre, "pre"}}};
static_assert(names_complete(kClassification));
constexpr NameTable<Precision, 2> kPrecision{
    {{Precision::double_precision, "double"}, {Precision::single_precision, "float"}}};
static_assert(names_complete(kPrecision));

}  // namespace

std::optional<OpacityUnit> parse_opacity_unit(std::string_view name) { return parse_name(kOpacityUnits, name); }
std::string opacity_unit_list() { return name_list(kOpacityUnits); }
std::string_view opacity_unit_name(OpacityUnit u) { return name_of(kOpacityUnits, u); }
std::optional<ColorConvention> parse_color_convention(std::string_view name) { return parse_name(kColors, name); }
std::string color_convention_list() { return name_list(kColors); }
std::string_view color_convention_name(ColorConvention c) { return name_of(kColors, c); }
std::optional<Compositing> parse_compositing(std::string_view name) { return parse_name(kCompositing, name); }
std::string compositing_list() { return name_list(kCompositing); }
std::string_view compositing_name(Compositing c) { return name_of(kCompositing, c); }
std::optional<Classification> parse_classification(std::string_view name) { return parse_name(kClassification, name); }
std::string classification_list() { return name_list(kClassification); }
std::string_view classification_name(Classification c) { return name_of(kClassification, c); }
std::optional<Precision> parse_precision(std::string_view name) { return parse_name(kPrecision, name); }
std::string precision_list() { return name_list(kPrecision); }
std::string_view precision_name(Precision p) { return name_of(kPrecision, p); }

void validate(const DiscreteConfig& c, bool grid_field) {
  if (c.oversample < 1 || c.oversample > 65536)
    throw OptionError(Option::oversample, fmt::format("must be in [1, 65536], got {}", c.oversample));
  const Strategy st = c.sampling.strategy;
  if (c.centred_oversamples && st != Strategy::step && st != Strategy::vtk && st != Strategy::inviwo)
    throw OptionError(Option::centred_oversamples,
                      fmt::format("needs a strategy whose first sample is at least half a step inside "
                                  "(step, vtk or inviwo), not {}", strategy_name(st)));
  // The partial step's own sample has no unit step to divide.
  if (c.oversample > 1 && (st == Strategy::partial || st == Strategy::exit_anchored))
    throw OptionError(Option::oversample, fmt::format("the {} strategy samples its partial step once; "
                                                      "oversample with step, vtk or inviwo", strategy_name(st)));
  if (c.correction != Correction::none && c.rule != SegmentRule::alpha)
    throw OptionError(Option::correction, fmt::format("only the alpha rule composites opacities (method is {})",
                                                      segment_rule_name(c.rule)));
  if (c.termination && !(*c.termination > 0 && *c.termination <= 1))
    throw OptionError(Option::termination, "must be in (0, 1]");
  if (c.skip_below && !(*c.skip_below >= 0 && *c.skip_below < 1))
    throw OptionError(Option::skip, "must be in [0, 1)");
  if (c.termination && c.compositing == Compositing::back_to_front)
    throw OptionError(Option::termination, "early termination needs front-to-back compositing");
  if (c.opacity_unit != OpacityUnit::per_sample && c.rule != SegmentRule::alpha)
    throw OptionError(Option::opacity_unit, fmt::format("only the alpha rule uses opacities (method is {})",
                                                        segment_rule_name(c.rule)));
  if (c.color != ColorConvention::straight && c.rule != SegmentRule::alpha)
    throw OptionError(Option::color, fmt::format("only the alpha rule composites colours (method is {})",
                                                 segment_rule_name(c.rule)));
  if (c.table_size != 0 && (c.table_size < 2 || c.table_size > kMaxTableSize))
    throw OptionError(Option::table_size,
                      fmt::format("must be 0 (no table) or in [2, {}], got {}", kMaxTableSize, c.table_size));
  if (c.table_size == 0 && c.table_lookup != TableLookup::centred)
    throw OptionError(Option::table_lookup, "needs {0} N (a table to read)", {Option::table_size});
  if (c.classification == Classification::pre && !grid_field)
    throw OptionError(Option::classification, "pre-classification needs a grid field");
  if (c.gradient == GradientScheme::nodes && !grid_field)
    throw OptionError(Option::gradient, "nodes (differences at the grid's nodes) needs a grid field");
  if (c.gradient_offset && (!(*c.gradient_offset > 0) || !std::isfinite(*c.gradient_offset)))
    throw OptionError(Option::gradient_offset, fmt::format("must be a positive finite length, got {}", *c.gradient_offset));
  if (c.gradient_offset && c.gradient != GradientScheme::central)
    throw OptionError(Option::gradient_offset, "applies to {0} central only", {Option::gradient});
  if (c.shade_at == ShadeAt::nodes && !grid_field)
    throw OptionError(Option::shade_at, "nodes (shading the grid's nodes) needs a grid field");
  if (c.shade_at == ShadeAt::nodes && (c.classification != Classification::pre || c.gradient != GradientScheme::nodes))
    throw OptionError(Option::shade_at, "nodes shades each node's classified colour with its node gradient: it needs "
                                        "{0} pre and {1} nodes", {Option::classification, Option::gradient});
}

void validate(const DiscreteConfig& c, bool grid_field, const TransferFunction& tf) {
  validate(c, grid_field);
  if (c.opacity_unit == OpacityUnit::per_unit_distance && tf.convention() != Convention::opacity_color)
    throw OptionError(Option::opacity_unit,
                      "distance needs an opacity/colour transfer function (emission and extinction "
                      "are per unit length already)");
}

DiscreteResult discrete_raycast(const Scene& scene, const Ray& ray, const DiscreteConfig& config) {
  return visit_field(scene, [&](const auto& field) {
    return scene_raycaster(field, scene, config).cast(ray);
  });
}

}  // namespace vrv
