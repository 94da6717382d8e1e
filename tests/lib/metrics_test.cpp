// The observed order of convergence is the least-squares slope of log(error) against log(step).
#include "lib/metrics.h"

#include <cmath>

#include <gtest/gtest.h>

namespace vrv {
namespace {

TEST(Metrics, ObservedOrderIsTheLeastSquaresSlope) {
  EXPECT_NEAR(observed_order({0.1, 0.05, 0.025}, {3e-2, 7.5e-3, 1.875e-3}), 2, 1e-12);
  EXPECT_TRUE(std::isnan(observed_order({0.1, 0.05}, {1e-3, 0})));
}

}  // namespace
}  // namespace vrv
