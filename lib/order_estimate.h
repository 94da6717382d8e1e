#pragma once
// The observed order of convergence with the spread of its fit, and the tolerance on it that the
// studies and tests derive from that spread (docs/studies.md, "Order tolerances").
//
// The order is the least-squares slope of log(error) against log(step) (Etiene et al., TVCG
// 2014); its standard error is sqrt(RSS / (n - 2) / Sxx), which measures how far the points bend
// away from one power law.  Why the spread bounds the slope's bias: if the error is
//   e(h) = C h^p (1 + D h^q),   D small,
// then log e = log C + p log h + D h^q, and the fitted slope is p + D * slope(h^q against log h)
// while the residual RSS is D^2 * RSS(h^q against log h).  Both scale with D, so
//   |fitted - p| = c_q(steps) * standard error
// exactly, with c_q depending on the steps alone.  c_q falls as q grows (the next term of an
// expansion in integer powers has q >= 1), so c_1 bounds it: 5.20 for three halving steps, 4.80
// for four, 4.50 for five.  The tolerance is max(margin * c_1 * SE, floor): the margin covers
// the terms beyond the second, the floor the bias the spread cannot see: two next-order terms
// can shift the slope while their curvatures cancel on the steps (segment-rules --quick, smooth
// scene, exact_linear: 0.020 off with SE 0.0009 on three steps).  The floor 0.05 is a twentieth
// of the gap between consecutive orders, five times tighter than the +-0.25 it replaces, and still
// rejects a rule of order p - 0.1.  Both are stated in each study file.
#include <vector>

namespace vrv {

struct OrderEstimate {
  double order;           // least-squares slope of log(error) against log(step); NaN if undefined
  double standard_error;  // of the slope; NaN with fewer than three points
  double bias_factor;     // c_1 above for these steps; NaN with fewer than three points
  long points;
};

// NaN order when there are fewer than two points, the sizes differ, or a step or an error is not
// finite and > 0.
OrderEstimate estimate_order(const std::vector<double>& steps, const std::vector<double>& errors);

// The same fit through points already taken to logarithms, x = log(step) and y = log(error), all
// finite and of equal number (the self-convergence order refits corrected y's, lib/metrics.h).
OrderEstimate estimate_log_order(const std::vector<double>& log_steps, const std::vector<double>& log_errors);

struct OrderTolerance {
  double margin = 2;     // times the bias bound c_1 * SE
  double floor = 0.05;   // the tolerance is never below this
};

// max(margin * bias_factor * standard_error, floor); NaN (so no order can match) when the fit
// has no spread to derive it from (fewer than three points).
double order_tolerance(const OrderEstimate& fit, const OrderTolerance& tolerance);

// |order - expected| <= order_tolerance; false whenever either is NaN.
bool order_matches(const OrderEstimate& fit, double expected, const OrderTolerance& tolerance);

}  // namespace vrv
