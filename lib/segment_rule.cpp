#include "lib/segment_rule.h"

#include <array>
#include <utility>

namespace vrv {
namespace {
constexpr std::array<std::pair<SegmentRule, std::string_view>, 5> kNames{{
    {SegmentRule::riemann, "riemann"},
    {SegmentRule::alpha, "alpha"},
    {SegmentRule::trapezoid, "trapezoid"},
    {SegmentRule::exact_linear, "exact_linear"},
    {SegmentRule::moreland, "moreland"},
}};
}  // namespace

std::optional<SegmentRule> parse_segment_rule(std::string_view name) {
  for (const auto& [rule, n] : kNames)
    if (n == name) return rule;
  return std::nullopt;
}

std::string_view segment_rule_name(SegmentRule r) {
  for (const auto& [rule, n] : kNames)
    if (rule == r) return n;
  return "?";
}

}  // namespace vrv
