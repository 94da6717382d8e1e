#pragma once
// The command line's adapters of the library's option declarations: the discrete options
// (lib/discrete_options.h), shared by `ray` and `render`, one flag per declared option with its help
// and default from the declaration; and the options several commands share (lib/shared_options.h).
#include <optional>
#include <string>
#include <string_view>

#include <CLI/CLI.hpp>

#include "lib/discrete_options.h"
#include "lib/shared_options.h"

namespace vrv::cli {

// Adds every option of discrete_option_fields() to the command, writing into `opt`; an option
// that needs a method is recorded in opt.given with the text the user typed.
void add_discrete_options(CLI::App& cmd, DiscreteOptions& opt);
// Refuses a value given as "" ("--method: must not be empty"): an empty string is how a text
// option says it was not given, so "" would silently mean the default.
// Inline: the Python module compiles projection_options.cpp, which uses it, without this file's .cpp.
inline CLI::Validator non_empty_value() {
  return CLI::Validator([](std::string& text) { return text.empty() ? std::string("must not be empty") : std::string(); },
                        "", "non-empty");
}

// A shared option's flag (--tol, --width, --height) writing into `value`, its help the library's
// with `note` (when the command uses it) appended; the command's default, where `value` has one,
// shown.
template <class T>
CLI::Option* add_shared_option(CLI::App& cmd, Option option, T& value, std::string_view note = {}) {
  std::string help(shared_option_help(option));
  if (!note.empty()) help += " " + std::string(note);
  CLI::Option* o = cmd.add_option(std::string(option_name(option, Spelling::flag)), value, help);
  if constexpr (requires { value.has_value(); }) {
    if (value) o->default_str(std::to_string(*value));  // CLI11 cannot print an optional's default
  } else {
    o->capture_default_str();
  }
  return o;
}

}  // namespace vrv::cli
