#include "studies/cli/discrete_flags.h"

#include <optional>
#include <string>
#include <type_traits>

namespace vrv::cli {
namespace {

template <class T>
struct is_optional : std::false_type {};
template <class T>
struct is_optional<std::optional<T>> : std::true_type {};

// One flag for a field: a bool is a switch; a field with a value of its own shows it as the
// default (an optional has none, and neither has the empty method).
template <class T>
CLI::Option* add_field(CLI::App& cmd, const std::string& flag, T& field, std::string_view help) {
  if constexpr (std::is_same_v<T, bool>) {
    return cmd.add_flag(flag, field, std::string(help));
  } else {
    CLI::Option* o = cmd.add_option(flag, field, std::string(help));
    if constexpr (std::is_same_v<T, std::string>) {
      o->check(non_empty_value());  // "" would be taken as not given (the reference, the default)
      if (!field.empty()) o->capture_default_str();
    } else if constexpr (!is_optional<T>::value) {
      o->capture_default_str();
    }
    return o;
  }
}

}  // namespace

void add_discrete_options(CLI::App& cmd, DiscreteOptions& opt) {
  for (const DiscreteOptionField& f : discrete_option_fields()) {
    const std::string flag(option_name(f.option, Spelling::flag));
    CLI::Option* o = std::visit([&](auto member) { return add_field(cmd, flag, opt.*member, f.help); }, f.member);
    if (f.needs_method) o->each([&opt, option = f.option](const std::string& text) { opt.give(option, text); });
  }
}

}  // namespace vrv::cli
