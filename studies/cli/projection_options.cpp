#include "studies/cli/projection_options.h"

#include <stdexcept>

#include <fmt/format.h>

#include "lib/option_error.h"

#include "studies/cli/cli_support.h"
#include "studies/cli/discrete_flags.h"

namespace vrv::cli {

void add_mode_option(CLI::App& cmd, std::string& mode) {
  cmd.add_option("--mode", mode,
                 "Projection instead of emission-absorption: xray | xray_classified | mip | mip_classified "
                 "(default: the scene's `mode`; emission_absorption overrides it) "
                 "(classified: of the transfer function's extinction); with --method, riemann | trapezoid | "
                 "simpson (X-ray) or max (MIP)")
      ->check(non_empty_value());
}

std::optional<ProjectionSetup> projection_setup(const std::string& mode, const DiscreteOptions& opt, const Scene& scene) {
  if (mode.empty()) return std::nullopt;
  const auto parsed = parse_projection_mode(mode);
  if (!parsed)
    throw OptionError(Option::mode, fmt::format("unknown value '{}' (one of {})", mode, projection_mode_list()));
  ProjectionSetup s;
  s.mode = *parsed;
  check_max_work(opt);
  for (const DiscreteOptionField& f : discrete_option_fields()) {
    const Option option = f.option;
    if (!opt.was_given(option)) continue;
    if (opt.method.empty()) throw OptionError(option, "applies to a discrete projection only; add {0}", {Option::method});
    if (option != Option::strategy && option != Option::rate && option != Option::step)
      throw OptionError(option, fmt::format("applies to emission-absorption raycasts, not to {{0}} {}", literal(mode)),
                        {Option::mode});
  }
  if (opt.method.empty()) return s;
  DiscreteProjectionConfig c;
  c.mode = s.mode;
  if (is_mip(s.mode)) {
    if (opt.method != "max")
      throw OptionError(Option::method,
                        fmt::format("unknown value '{}' for {{0}} {} (max)", literal(opt.method), literal(mode)),
                        {Option::mode});
  } else {
    const auto rule = parse_xray_rule(opt.method);
    if (!rule)
      throw OptionError(Option::method,
                        fmt::format("unknown value '{}' for {{0}} {} ({})", literal(opt.method), literal(mode),
                                    xray_rule_list()),
                        {Option::mode});
    c.rule = *rule;
  }
  c.sampling = sampling_config(opt, scene);
  s.discrete = c;
  DiscreteConfig work;
  work.sampling = c.sampling;
  s.work = work;
  return s;
}

nlohmann::ordered_json to_json(const ProjectionResult& r, ProjectionMode mode) {
  nlohmann::ordered_json j;
  j["mode"] = projection_mode_name(mode);
  j["value"] = finite_or_null(r.value);
  j["error_estimate"] = finite_or_null(r.error_estimate);
  j["evaluations"] = r.evaluations;
  j["t_entry"] = r.hit ? nlohmann::ordered_json(r.t_entry) : nlohmann::ordered_json(nullptr);
  j["t_exit"] = r.hit ? nlohmann::ordered_json(r.t_exit) : nlohmann::ordered_json(nullptr);
  if (is_mip(mode)) {
    j["position"] = finite_or_null(r.position);
    j["ambiguous"] = r.ambiguous;
  }
  j["tolerance_met"] = r.tolerance_met;
  return j;
}

nlohmann::ordered_json to_json(const DiscreteProjectionResult& r, ProjectionMode mode) {
  nlohmann::ordered_json j;
  j["mode"] = projection_mode_name(mode);
  j["value"] = finite_or_null(r.value);
  j["samples"] = r.samples;
  if (is_mip(mode)) j["position"] = finite_or_null(r.position);
  return j;
}

}  // namespace vrv::cli
