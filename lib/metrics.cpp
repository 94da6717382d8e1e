#include "lib/metrics.h"

#include <cmath>
#include <limits>

#include <Eigen/Dense>

namespace vrv {

double observed_order(const std::vector<double>& steps, const std::vector<double>& errors) {
  if (steps.size() < 2 || steps.size() != errors.size()) return std::numeric_limits<double>::quiet_NaN();
  Eigen::MatrixXd A(steps.size(), 2);
  Eigen::VectorXd b(steps.size());
  for (std::size_t i = 0; i < steps.size(); ++i) {
    if (!(errors[i] > 0) || !std::isfinite(errors[i])) return std::numeric_limits<double>::quiet_NaN();
    A(static_cast<Eigen::Index>(i), 0) = std::log(steps[i]);
    A(static_cast<Eigen::Index>(i), 1) = 1;
    b(static_cast<Eigen::Index>(i)) = std::log(errors[i]);
  }
  return A.colPivHouseholderQr().solve(b)(0);
}

}  // namespace vrv
