#pragma once
// The command-line options that configure a discrete raycast, shared by `ray` and `render`.
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "lib/discrete_raycast.h"
#include "lib/option_error.h"
#include "lib/scene.h"
#include "lib/work_estimate.h"

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
  std::string gradient = "central";
  std::optional<double> gradient_offset;
  std::string shade_at = "samples";
  // Every option above except --method: each is refused without --method (it would do nothing).
  std::vector<CLI::Option*> given;
  // Work limit, for the reference too: a run whose field evaluations (estimated before anything
  // is cast, lib/work_estimate.h) exceed it is refused.  1e9 is about a minute to a few minutes
  // on one core.
  double max_work = 1e9;
};

void add_discrete_options(CLI::App& cmd, DiscreteOptions& opt);
// The configuration, or nothing when no --method asks for a discrete raycast.  Throws
// OptionError (a std::invalid_argument; each front end spells the option as its user wrote it)
// for a bad value or combination, or for a discrete option given without --method.
std::optional<DiscreteConfig> discrete_config(const DiscreteOptions& opt, const Scene& scene);
// The Option (lib/option_error.h) of one of DiscreteOptions::given.
Option given_option(const CLI::Option& o);
// OptionError(Option::max_work) unless positive.
void check_max_work(const DiscreteOptions& opt);

// The sample placement of --strategy, --rate and --step (shared by the projections' discrete
// modes); throws OptionError.
SamplingConfig sampling_config(const DiscreteOptions& opt, const Scene& scene);

// Throws the refusal: `discrete` says whether the work is samples or the reference's evaluations.
[[noreturn]] void refuse_work(const DiscreteOptions& opt, bool discrete, double work, long rays);

// The work of casting these rays, without a limit (check_work below compares it with one).  An RGB
// scene's discrete cast samples every channel (alpha costs none: it is the casts' transmittance);
// its reference evaluates the field once for all.
template <class RayAt>
double estimate_work(const std::optional<DiscreteConfig>& config, double tol, const Scene& scene, long rays,
                     RayAt&& ray_at) {
  double work = 0;
  for (long i = 0; i < rays; ++i)
    work += config ? discrete_samples(*config, scene, ray_at(i)) * scene.channel_count()
                   : reference_evaluations(scene, ray_at(i), tol);
  return work;
}

// The work of one ray along the box's diagonal, an upper estimate for any ray (what a rays file
// is counted against before it is read).
double diagonal_work(const std::optional<DiscreteConfig>& config, double tol, const Scene& scene);

// The work of casting these rays, in field evaluations (lib/work_estimate.h): the discrete
// raycast's samples (its sample plans, before early termination), or with no configuration the
// reference's evaluations at `tol`.  Throws std::invalid_argument when it exceeds opt.max_work,
// with the estimate, the options that ask for it and the option that allows it (--max-work).
template <class RayAt>
double check_work(const DiscreteOptions& opt, const std::optional<DiscreteConfig>& config, double tol,
                  const Scene& scene, long rays, RayAt&& ray_at) {
  const double work = estimate_work(config, tol, scene, rays, ray_at);
  if (work > opt.max_work) refuse_work(opt, config.has_value(), work, rays);
  return work;
}

}  // namespace vrv::cli
