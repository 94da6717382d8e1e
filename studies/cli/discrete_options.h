#pragma once
// The command-line options that configure a discrete raycast, shared by `ray` and `render`.
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "lib/discrete_raycast.h"
#include "lib/scene.h"

namespace vrv::cli {

struct DiscreteOptions {
  std::string method;  // empty: the reference integrator
  std::optional<std::string> strategy;  // default entry_exit_corner, or step with --step
  std::optional<double> rate;
  std::optional<double> step;
  int oversample = 1;
  bool centred_oversamples = false;
  std::string correction = "none";
  std::optional<double> termination;
  std::optional<double> skip;
  std::string compositing = "front_to_back";
  std::string classification = "post";
  std::string precision = "double";
  std::string opacity_unit = "sample";
  std::string color = "straight";
  int table_size = 0;
  std::string table_lookup = "centred";
};

void add_discrete_options(CLI::App& cmd, DiscreteOptions& opt);
// The configuration, or nothing when no --method asks for a discrete raycast.  Throws
// std::invalid_argument naming the option for a bad value or combination.
std::optional<DiscreteConfig> discrete_config(const DiscreteOptions& opt, const Scene& scene);

}  // namespace vrv::cli
