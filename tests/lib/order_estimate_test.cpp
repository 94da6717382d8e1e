// The observed order with its spread, and the tolerance derived from it (lib/order_estimate.h).
#include "lib/order_estimate.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace vrv {
namespace {

std::vector<double> halving(double h0, int n) {
  std::vector<double> h;
  for (int i = 0; i < n; ++i) h.push_back(h0 / std::pow(2.0, i));
  return h;
}

TEST(OrderEstimate, APowerLawHasItsOrderAndNoSpread) {
  const std::vector<double> h = halving(0.1, 4);
  std::vector<double> e;
  for (double x : h) e.push_back(3 * x * x);
  const OrderEstimate f = estimate_order(h, e);
  EXPECT_NEAR(f.order, 2, 1e-13);
  EXPECT_LT(f.standard_error, 1e-13);
  EXPECT_EQ(f.points, 4);
  // No spread: the tolerance is the floor, and an order 0.06 off fails it.
  EXPECT_EQ(order_tolerance(f, OrderTolerance{2, 0.05}), 0.05);
  EXPECT_TRUE(order_matches(f, 2, OrderTolerance{2, 0.05}));
  EXPECT_FALSE(order_matches(f, 2.06, OrderTolerance{2, 0.05}));
}

TEST(OrderEstimate, TheBiasFactorIsTheTwoTermModelsBiasPerStandardError) {
  // e = h^2 (1 + D h), D small: the fitted order is off by exactly bias_factor x SE.
  for (int n : {3, 4, 5}) {
    const std::vector<double> h = halving(0.04, n);
    std::vector<double> e;
    for (double x : h) e.push_back(x * x * std::exp(1e-3 * x / h[0]));  // log e = 2 log h + D h
    const OrderEstimate f = estimate_order(h, e);
    EXPECT_NEAR(std::abs(f.order - 2), f.bias_factor * f.standard_error, 1e-9) << n;
  }
  EXPECT_NEAR(estimate_order(halving(1, 3), {1, 0.3, 0.1}).bias_factor, 5.196, 1e-3);
  EXPECT_NEAR(estimate_order(halving(1, 4), {1, 0.3, 0.1, 0.02}).bias_factor, 4.796, 1e-3);
  EXPECT_NEAR(estimate_order(halving(1, 5), {1, 0.3, 0.1, 0.02, 0.01}).bias_factor, 4.500, 1e-3);
}

TEST(OrderEstimate, TooFewOrBadPointsGiveNoTolerance) {
  const OrderEstimate two = estimate_order({0.1, 0.05}, {1e-2, 2.5e-3});
  EXPECT_NEAR(two.order, 2, 1e-13);
  EXPECT_TRUE(std::isnan(two.standard_error));
  EXPECT_TRUE(std::isnan(order_tolerance(two, OrderTolerance{})));
  EXPECT_FALSE(order_matches(two, 2, OrderTolerance{}));  // no spread to derive it from: fails
  EXPECT_TRUE(std::isnan(estimate_order({0.1, 0.05, 0.025}, {1e-2, 0, 1e-4}).order));
  EXPECT_TRUE(std::isnan(estimate_order({0.1, 0.05, 0.025}, {1e-2, NAN, 1e-4}).order));
  EXPECT_TRUE(std::isnan(estimate_order({0.1, 0.05}, {1e-2}).order));
}

}  // namespace
}  // namespace vrv
