#pragma once
// The command-line options that configure a discrete raycast, shared by `ray` and `render`.
#include <optional>
#include <string>
#include <vector>

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
  // Work limit: a run whose samples (estimated from the sample plans before anything is cast)
  // exceed it is refused.  1e9 samples is about a minute to a few minutes on one core.
  double max_work = 1e9;
  // Every option above except --method: each is refused without --method (it would do nothing).
  std::vector<CLI::Option*> given;
};

void add_discrete_options(CLI::App& cmd, DiscreteOptions& opt);
// The configuration, or nothing when no --method asks for a discrete raycast.  Throws
// std::invalid_argument naming the option for a bad value or combination, or for a discrete
// option given without --method.
std::optional<DiscreteConfig> discrete_config(const DiscreteOptions& opt, const Scene& scene);

// The samples the raycast takes on these rays (before early termination), from the sample plans
// alone.  Throws std::invalid_argument when they exceed opt.max_work, with the estimate, the
// refinement options that ask for it and the option that allows it (--max-work).
template <class RayAt>
double check_work(const DiscreteOptions& opt, const DiscreteConfig& config, const Scene& scene,
                  long rays, RayAt&& ray_at);
double samples_on_ray(const DiscreteConfig& config, const Scene& scene, const Ray& ray);
void refuse_work(const DiscreteOptions& opt, double samples, long rays);

template <class RayAt>
double check_work(const DiscreteOptions& opt, const DiscreteConfig& config, const Scene& scene,
                  long rays, RayAt&& ray_at) {
  double samples = 0;
  for (long i = 0; i < rays; ++i) samples += samples_on_ray(config, scene, ray_at(i));
  if (samples > opt.max_work) refuse_work(opt, samples, rays);
  return samples;
}

}  // namespace vrv::cli
