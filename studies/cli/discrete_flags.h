#pragma once
// The command line's adapter of the discrete options (lib/discrete_options.h), shared by `ray`
// and `render`: one flag per declared option, with its help and default from the declaration.
#include <CLI/CLI.hpp>

#include "lib/discrete_options.h"

namespace vrv::cli {

// Adds every option of discrete_option_fields() to the command, writing into `opt`; an option
// that needs a method is recorded in opt.given with the text the user typed.
void add_discrete_options(CLI::App& cmd, DiscreteOptions& opt);

}  // namespace vrv::cli
