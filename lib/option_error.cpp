#include "lib/option_error.h"

#include <array>

#include <fmt/args.h>
#include <fmt/format.h>

#include "lib/util/enum_names.h"

namespace vrv {
namespace {

constexpr NameTable<Option, static_cast<std::size_t>(kLastOption) + 1> kKeys{{{Option::method, "method"},
                                       {Option::strategy, "strategy"},
                                       {Option::rate, "rate"},
                                       {Option::step, "step"},
                                       {Option::oversample, "oversample"},
                                       {Option::centred_oversamples, "centred_oversamples"},
                                       {Option::correction, "correction"},
                                       {Option::termination, "termination"},
                                       {Option::skip, "skip"},
                                       {Option::compositing, "compositing"},
                                       {Option::classification, "classification"},
                                       {Option::precision, "precision"},
                                       {Option::opacity_unit, "opacity_unit"},
                                       {Option::color, "color"},
                                       {Option::table_size, "table_size"},
                                       {Option::table_lookup, "table_lookup"},
                                       {Option::mode, "mode"},
                                       {Option::max_work, "max_work"},
                                       {Option::gradient, "gradient"},
                                       {Option::gradient_offset, "gradient_offset"},
                                       {Option::shade_at, "shade_at"},
                                       {Option::tol, "tol"},
                                       {Option::width, "width"},
                                       {Option::height, "height"},
                                       {Option::threshold, "threshold"},
                                       {Option::expected_order, "expected_order"},
                                       {Option::order_tolerance, "order_tolerance"},
                                       {Option::order_metric, "order_metric"},
                                       {Option::unit_distance, "unit_distance"},
                                       {Option::alpha, "alpha"},
                                       {Option::target, "target"},
                                       {Option::metric, "metric"},
                                       {Option::rules, "rules"},
                                       {Option::table_points, "table_points"},
                                       {Option::resolution, "resolution"}}};

// Every option once, in the enum's order (an entry left out would be a default, unnamed one).
constexpr bool every_option_once() {
  for (std::size_t i = 0; i < kKeys.size(); ++i)
    if (static_cast<std::size_t>(kKeys[i].first) != i || kKeys[i].second.empty()) return false;
  return true;
}
static_assert(every_option_once(), "kKeys: one entry per Option, in order");

// The flag is the key with '-' for '_' behind "--": derived, so the two can never disagree.
std::string flag_of(std::string_view key) {
  std::string flag = "--" + std::string(key);
  for (char& c : flag)
    if (c == '_') c = '-';
  return flag;
}

}  // namespace

std::string_view option_name(Option option, Spelling spelling) {
  static const auto flags = [] {
    std::array<std::string, kKeys.size()> f;
    for (std::size_t i = 0; i < kKeys.size(); ++i) f[static_cast<std::size_t>(kKeys[i].first)] = flag_of(kKeys[i].second);
    return f;
  }();
  if (spelling == Spelling::key) return name_of(kKeys, option);
  return flags[static_cast<std::size_t>(option)];
}

std::optional<Option> option_from_flag(std::string_view flag) {
  for (const auto& [option, key] : kKeys)
    if (option_name(option, Spelling::flag) == flag) return option;
  return std::nullopt;
}

std::string literal(std::string_view text) {
  std::string out;
  for (char c : text) {
    out += c;
    if (c == '{' || c == '}') out += c;
  }
  return out;
}

std::string OptionError::spelled(const std::string& reason, const std::vector<Option>& mentioned,
                                 Spelling spelling) {
  // Only a reason that mentions options is a format string: a value the user typed, such as
  // '{', in a plain reason made "invalid format string" the whole message.
  if (mentioned.empty()) return reason;
  fmt::dynamic_format_arg_store<fmt::format_context> names;
  for (Option o : mentioned) names.push_back(std::string(option_name(o, spelling)));
  return fmt::vformat(reason, names);
}

OptionError::OptionError(Option option, std::string reason, std::vector<Option> mentioned)
    : std::invalid_argument(fmt::format("{}: {}", option_name(option, Spelling::flag),
                                        spelled(reason, mentioned, Spelling::flag))),
      option_(option),
      reason_(std::move(reason)),
      mentioned_(std::move(mentioned)) {}

std::string OptionError::reason(Spelling spelling) const { return spelled(reason_, mentioned_, spelling); }

std::string OptionError::message(Spelling spelling) const {
  return fmt::format("{}: {}", option_name(option_, spelling), reason(spelling));
}

}  // namespace vrv
