#pragma once
// Running the sampling study: the fan (per-ray curves, error table, observed orders), the images,
// the checks, and the files (rays.csv, errors.*, summary.*, images.csv, EXR/PNG, plots.json).
#include <optional>
#include <string>
#include <vector>

#include "analytic/linear_ramp.h"
#include "studies/engine/study_driver.h"
#include "studies/sampling/fan.h"

namespace vrv::sampling_study {

// Everything the study file says (see studies/sampling/sampling.toml and docs/study-sampling.md).
struct Study {
  std::string name;
  Scene scene;
  std::string scene_toml;
  LinearRamp ramp;  // the grid's source: the identity check's field
  double reference_tol = 1e-13;
  std::vector<Strategy> strategies;
  FanSetup setup;
  std::vector<double> curve_rates, order_rates, image_rates;
  int width = 500, height = 500, quick_width = 100, quick_height = 100;
  double identity_tol = 1e-12;
  std::optional<double> closed_form_kappa;  // g = kappa tau, both linear: I = kappa (1 - e^-Phi)
  // Rules for the error table and orders; the first is the paper's eq. (5) (riemann), which the
  // curves and images use.
  std::vector<SegmentRule> rules{SegmentRule::riemann};
  struct OrderBound {
    SegmentRule rule;
    std::vector<Strategy> strategies;
    double min_order = 0.75;
  };
  std::vector<OrderBound> order_bounds;
  struct ExactBound {  // a configuration that must reproduce the continuous solution
    SegmentRule rule;
    std::vector<Strategy> strategies;
    double max_error = 1e-12;
  };
  std::vector<ExactBound> exact_bounds;
  std::vector<Strategy> keeps_every_ray, drops_corner_rays;
};

// The same scene with the grid replaced by the ramp it samples (dims kept: same sample plans).
Scene ramp_scene(const Study& st);

// One strategy at one rate on a set of rays (the fan, or an image's pixels).
struct StrategyRun {
  SegmentRule rule;
  Strategy strategy;
  double rate = 1;
  std::vector<RayValue> rays;
  FanStats stats;
};

// Observed order: least-squares slope of log(error) against log(1/rate) (lib/metrics.h).
double order_over_rates(const std::vector<double>& rates, const std::vector<double>& errors);

// Per rule and strategy: orders of the max and of the mean error over the runs at orders.rates;
// NaN (no order) when every error is at rounding level (<= identity_tol): the method is exact.
struct StrategyOrder {
  SegmentRule rule;
  Strategy strategy;
  double order_max = 0, order_mean = 0;
};
std::vector<StrategyOrder> observed_orders(const Study& st, const std::vector<StrategyRun>& runs);

// The paper's closed form for g = kappa tau with tau linear in s and s linear along the ray:
// I = kappa (1 - e^-Phi), Phi = L (tau(f_in) + tau(f_out)) / 2 (I0 = 0); 0 for a miss.
double closed_form(const Study& st, const Ray& ray, double kappa);

StudyOutcome run_sampling_study(const Study& st, const StudyRun& run);

// Field evaluations of the run (full or `quick`), estimated from the study alone.
StudyWork sampling_work(const Study& st, bool quick);

}  // namespace vrv::sampling_study
