#include "lib/segment_rule.h"

#include <array>

#include "lib/util/enum_names.h"

namespace vrv {
namespace {
constexpr NameTable<SegmentRule, 5> kSegmentRuleNames{{
    {SegmentRule::riemann, "riemann"},
    {SegmentRule::alpha, "alpha"},
    {SegmentRule::trapezoid, "trapezoid"},
    {SegmentRule::exact_linear, "exact_linear"},
    {SegmentRule::moreland, "moreland"},
}};
static_assert(names_complete(kSegmentRuleNames));
}  // namespace

std::optional<SegmentRule> parse_segment_rule(std::string_view name) { return parse_name(kSegmentRuleNames, name); }
std::string segment_rule_list() { return name_list(kSegmentRuleNames); }

std::string_view segment_rule_name(SegmentRule r) { return name_of(kSegmentRuleNames, r); }

std::span<const SegmentRule> all_segment_rules() {
  static const auto rules = [] {
    std::array<SegmentRule, kSegmentRuleNames.size()> out{};
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = kSegmentRuleNames[i].first;
    return out;
  }();
  return rules;
}

}  // namespace vrv
