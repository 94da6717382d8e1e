#pragma once
// Where a discrete raycast puts its samples along a ray: the published sample-placement
// strategies and the conventions of two renderers.  See docs/sampling.md (formulas, borders and
// corners, what VTK and Inviwo actually do) and docs/discrete-raycasts.md.
#include <array>
#include <optional>
#include <vector>
#include <string>
#include <span>
#include <string_view>

#include "lib/geometry.h"

namespace vrv {

enum class Strategy {
  eye,                // Listing 1 of Steneteg et al.: aligned with the eye, rate-based step
  entry,              // Listing 2: first sample half a step inside the entry
  entry_exit,         // Listing 3: floor(samples), half a step inside both ends
  entry_exit_corner,  // Listing 4: ceil(rate * length(ray * (dims - 1))), keeps corner rays
  step,               // fixed world step H, first sample H/2 inside
  vtk,                // fixed step H, first sample one full step inside, last partial step dropped
  inviwo,             // step rounded so a whole number of steps fits, samples at midpoints
  partial,            // fixed step H at midpoints from the entry; the partial step left at the
                      // exit sampled at its own midpoint, for its own length
  exit_anchored,      // the same anchored at the exit (a back-to-front march): whole steps back
                      // from the exit at midpoints, the partial step at the entry at its midpoint
};

// Names: "eye", "entry", "entry_exit", "entry_exit_corner", "step", "vtk", "inviwo", "partial",
// "exit_anchored".
std::optional<Strategy> parse_strategy(std::string_view name);
std::string strategy_list();  // its names in order, "a, b, c": the choices an error offers
std::string strategy_list(std::span<const Strategy> strategies);  // those names, "a, b, c"
std::string_view strategy_name(Strategy s);
// The strategies `keep` picks, in the order above (what a study or command takes, for its errors).
std::vector<Strategy> strategies_where(bool (*keep)(Strategy));
// The step-based strategies without a partial step (partial and exit_anchored sample one at an end).
inline constexpr Strategy kWholeStepStrategies[] = {Strategy::step, Strategy::vtk, Strategy::inviwo};

// Whether the strategy places samples by a world step (SamplingConfig::step) rather than a rate.
bool step_based(Strategy st);

struct SamplingConfig {
  Strategy strategy = Strategy::entry_exit_corner;
  double rate = 1;                        // samples per voxel (eye, entry, entry_exit, corner)
  double step = 0;                        // world step H (step, vtk, inviwo)
  std::array<int, 3> dims{64, 64, 64};    // voxel grid that turns `rate` into a step
  std::optional<Vec3> eye;                // eye position for `eye` (default: the ray origin)
};

// Samples at t = t_first + k * dt for k = 0, 1, ... while t < t_end (world parameter along the
// ray, as Ray::at), each standing for a world length dt.  count is that number (may be 0), and
// it is exact for this predicate: t(k) < t_end for every k < count and t(count) >= t_end, with
// t(k) evaluated as below (no running sums), so `for (k = 0; k < count; ++k)` and
// `for (k = 0; t(k) < t_end; ++k)` visit the same samples.
// t_end is iv.t1, except for Strategy::partial and exit_anchored (the end of the whole steps,
// before the partial step or after it) and Strategy::vtk, whose loop keeps a sample lying exactly on the exit
// (t <= iv.t1): there t_end = nextafter(iv.t1, +inf).  A plan without samples has count 0 and
// t(0) >= t_end; dt is then the step the strategy would have used, or 0 (never NaN or inf).
struct SamplePlan {
  double t_first = 0;
  double dt = 0;
  double t_end = 0;
  long count = 0;
  // Strategies partial and exit_anchored: one more sample, at t_partial, standing for its own
  // length `partial` (the partial step a whole number of steps leaves); before the others when
  // partial_first (exit_anchored), after them otherwise.  partial 0: none.
  double partial = 0, t_partial = 0;
  bool partial_first = false;
  double t(long k) const { return t_first + static_cast<double>(k) * dt; }
};

// Throws OptionError (naming the rate or the step) unless the one the strategy uses is positive
// and finite.
void check_sampling(const SamplingConfig& config);

// The plan for a ray whose clipped range is iv (as clip(ray, box)).  The rate-based strategies
// work in texture space (box -> [0,1]^3) exactly as Listings 1-4 and map back to world units.
// A zero-length range gives count 0.  Throws std::invalid_argument for a non-positive or
// non-finite rate (message names --rate) or step (names --step), for dims < 1 or a box without
// volume (rate-based strategies only), and when the plan would exceed 10^12 samples.
SamplePlan plan_samples(const SamplingConfig& config, const Ray& ray, Interval iv, const Box& box);

}  // namespace vrv
