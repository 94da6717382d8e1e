#pragma once
// Error statistics of discrete results against the reference: the observed order of convergence.
#include <vector>

namespace vrv {

// Least-squares slope of log(error) against log(step) (Eigen).  NaN if fewer than two points
// or an error is not positive.
double observed_order(const std::vector<double>& steps, const std::vector<double>& errors);

}  // namespace vrv
