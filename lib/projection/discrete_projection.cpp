#include "lib/projection/discrete_projection.h"

#include "lib/util/enum_names.h"

namespace vrv {
namespace {

constexpr NameTable<XrayRule, 3> kRules{{
    {XrayRule::riemann, "riemann"},
    {XrayRule::trapezoid, "trapezoid"},
    {XrayRule::simpson, "simpson"},
}};
static_assert(names_complete(kRules));

}  // namespace

std::optional<XrayRule> parse_xray_rule(std::string_view name) { return parse_name(kRules, name); }
std::string xray_rule_list() { return name_list(kRules); }
std::string_view xray_rule_name(XrayRule r) { return name_of(kRules, r); }

DiscreteProjectionResult discrete_projection(const Scene& scene, const Ray& ray, const DiscreteProjectionConfig& config) {
  return visit_field(scene, [&](const auto& field) { return discrete_projection(field, scene.box, scene.transfer, ray, config); });
}

}  // namespace vrv
