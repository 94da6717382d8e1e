#include "lib/segment_rule.h"

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

std::string_view segment_rule_name(SegmentRule r) { return name_of(kSegmentRuleNames, r); }

}  // namespace vrv
