#pragma once
// The options of a discrete raycast as a user gives them, declared once: each option's field (its
// default is the field's initializer), its help text and its place in one table
// (discrete_option_fields), and discrete_config(), the one place they are checked and turned into
// a DiscreteConfig.  The front ends are thin adapters that fill DiscreteOptions from the table:
// the command line (studies/cli/discrete_flags), study files (read_study_method, lib/study_file)
// and Python keywords (studies/python/module.cpp).  Names and spellings: lib/option_error.
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "lib/discrete_raycast.h"
#include "lib/option_error.h"
#include "lib/scene.h"
#include "lib/work_estimate.h"

namespace vrv {

struct DiscreteOptions {
  std::string method;  // empty: the reference integrator
  std::optional<std::string> strategy;  // default entry_exit_corner, or step with a step
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
  // Work limit, for the reference too: a run whose field evaluations (estimated before anything
  // is cast, lib/work_estimate.h) exceed it is refused.  1e9 is about a minute to a few minutes
  // on one core.
  double max_work = 1e9;

  // The options the user gave that need a method (every one above but method and max_work), with
  // the text they gave (the work refusal quotes it): each is refused without a method.
  std::vector<std::pair<Option, std::string>> given;
  void give(Option option, std::string text);
  bool was_given(Option option) const;
  // The text given for the option, or nullptr.
  const std::string* given_text(Option option) const;
};

// One option's declaration: its field and help.  `needs_method`: refused without a method
// (adapters record it in DiscreteOptions::given when the user gives it).
struct DiscreteOptionField {
  using Member = std::variant<std::string DiscreteOptions::*, std::optional<std::string> DiscreteOptions::*,
                              std::optional<double> DiscreteOptions::*, double DiscreteOptions::*,
                              int DiscreteOptions::*, bool DiscreteOptions::*>;
  Option option;
  Member member;
  std::string_view help;
  bool needs_method = true;
};

// Every option of DiscreteOptions, in the order the command line's help lists them.
std::span<const DiscreteOptionField> discrete_option_fields();
// The declaration of one option, or nullptr for an option that is not a discrete raycast's (mode).
const DiscreteOptionField* discrete_option_field(Option option);

// The configuration, or nothing when no method asks for a discrete raycast.  Throws OptionError
// (a std::invalid_argument; each front end spells the option as its user wrote it) for a bad
// value or combination, or for a discrete option given without a method.
std::optional<DiscreteConfig> discrete_config(const DiscreteOptions& opt, const Scene& scene);
// OptionError(Option::max_work) unless positive.
void check_max_work(const DiscreteOptions& opt);

// The sample placement of strategy, rate and step (shared by the projections' discrete modes);
// throws OptionError.
SamplingConfig sampling_config(const DiscreteOptions& opt, const Scene& scene);

// Throws the refusal: `discrete` says whether the work is samples or the reference's evaluations.
// The message names the options as the command line spells them (Python's refusals are the
// command line's, word for word).
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

}  // namespace vrv
