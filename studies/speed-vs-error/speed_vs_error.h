#pragma once
// Speed against error (kind "speed_vs_error"): every method at every refinement on one ray set,
// its error against an independent truth (the test suite's long-double integrator, which shares
// no code with the reference integrator it also scores; the reference at reference_tol is checked
// against it) and its single-thread time per ray; the Pareto front; and per target error the
// cheapest configuration of each method reaching it.
// See docs/study-speed-vs-error.md.
#include <optional>
#include <string>
#include <vector>

namespace vrv {

// One configuration's row.
struct SpeedErrorPoint {
  std::string method;             // the series: the method's label, else its name ("reference", "riemann", ...)
  double level = 0;               // the tolerance or the step
  double max_error = 0, mean_error = 0;  // over the rays, |value - truth|
  double max_estimate = 0;        // reference rows: largest own error estimate; else 0
  double seconds_per_ray = 0;     // single thread, best of the repeats
  double work_per_ray = 0;        // field evaluations (reference) or samples (discrete)
  bool reference = false;         // the reference integrator's row (whatever its label)
  // What `level` is: the reference's tolerance or a discrete method's step.
  const char* level_name() const { return reference ? "tol" : "step"; }
};

// Which points are on the Pareto front of (cost, error), both minimised: no other point is at
// least as good in both and better in one.  Equal points are all on the front.
std::vector<bool> pareto_front(const std::vector<double>& cost, const std::vector<double>& error);

// Among `points` of `method`, the index of the one with the least seconds_per_ray whose
// max_error <= target; nullopt when none reaches it.
std::optional<std::size_t> cheapest_reaching(const std::vector<SpeedErrorPoint>& points,
                                             const std::string& method, double target);

}  // namespace vrv
