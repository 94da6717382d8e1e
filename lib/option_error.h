#pragma once
// One vocabulary for the options the library checks (a discrete raycast's, the reference's
// tolerance, an image's size, verify's and plan's): each option's command-line flag and its key
// (study files, bounds files, Python keywords) in one table.  The library's checks throw OptionError naming
// the option by id; each front end spells it as its user wrote it (`--table-size` on the command
// line, `table_size` in a study file or a Python call), so no message names an option the user
// never typed.
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace vrv {

enum class Option {
  method, strategy, rate, step, oversample, centred_oversamples, correction, termination, skip,
  compositing, classification, precision, opacity_unit, color, table_size, table_lookup, mode, max_work,
  gradient, gradient_offset, shade_at,
  tol, width, height,                                                         // the reference, an image
  threshold, expected_order, order_tolerance, order_metric, unit_distance, alpha,  // verify
  target, metric, rules,                                                       // plan
  table_points, resolution                                                     // the exports
};
inline constexpr Option kLastOption = Option::resolution;  // for loops over every option

enum class Spelling { flag, key };  // --table-size, table_size

std::string_view option_name(Option option, Spelling spelling);
// The option a command-line flag names ("--table-size"), if it is one of these.
std::optional<Option> option_from_flag(std::string_view flag);
// A user's text inside a reason that mentions options ({0}, ...): its braces doubled, so that
// a value such as '{x}' is shown as typed (a reason without mentions is taken as it is).
std::string literal(std::string_view text);

class OptionError : public std::invalid_argument {
 public:
  // `reason` names other options as {0}, {1}, ... in the order of `mentioned`.
  OptionError(Option option, std::string reason, std::vector<Option> mentioned = {});
  Option option() const { return option_; }
  // The reason with the options it mentions spelled as `spelling`.
  std::string reason(Spelling spelling) const;
  // "<option>: <reason>"; what() is the command line's (Spelling::flag).
  std::string message(Spelling spelling) const;

 private:
  static std::string spelled(const std::string& reason, const std::vector<Option>& mentioned, Spelling spelling);
  Option option_;
  std::string reason_;
  std::vector<Option> mentioned_;
};

}  // namespace vrv
