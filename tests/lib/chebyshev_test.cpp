#include "lib/chebyshev.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace vrv {
namespace {

std::vector<double> coefficients_of(double (*f)(double), int n) {
  const ChebyshevRule& rule = ChebyshevRule::get(n);
  std::vector<double> values(n), c(n);
  for (int j = 0; j < n; ++j) values[j] = f(rule.node(j));
  rule.coefficients(values, c);
  return c;
}

TEST(Chebyshev, PolynomialsAreReproducedExactly) {
  // T_3(x) = 4x^3 - 3x: coefficients (0, 0, 0, 1).
  auto c = coefficients_of([](double x) { return 4 * x * x * x - 3 * x; }, 4);
  EXPECT_NEAR(c[0], 0, 1e-15);
  EXPECT_NEAR(c[1], 0, 1e-15);
  EXPECT_NEAR(c[2], 0, 1e-15);
  EXPECT_NEAR(c[3], 1, 1e-15);
  for (double x : {-1.0, -0.3, 0.0, 0.7, 1.0})
    EXPECT_NEAR(chebyshev_evaluate(c, x), 4 * x * x * x - 3 * x, 1e-15);
}

TEST(Chebyshev, InterpolatesSmoothFunctionsSpectrally) {
  auto c = coefficients_of([](double x) { return std::exp(x) * std::sin(3 * x); }, 33);
  for (double x = -1; x <= 1; x += 0.01)
    EXPECT_NEAR(chebyshev_evaluate(c, x), std::exp(x) * std::sin(3 * x), 2e-15);
  const ChebyshevAccuracy acc = chebyshev_accuracy(c);
  EXPECT_TRUE(acc.resolved);
  EXPECT_LT(acc.error, 1e-14);
}

TEST(Chebyshev, IntegralAndAntiderivative) {
  auto c = coefficients_of([](double x) { return std::exp(x); }, 33);
  EXPECT_NEAR(chebyshev_integral(c), std::exp(1.0) - std::exp(-1.0), 1e-15);
  std::vector<double> anti(c.size() + 1);
  chebyshev_antiderivative(c, anti);
  for (double x : {-1.0, -0.5, 0.25, 1.0})
    EXPECT_NEAR(chebyshev_evaluate(anti, x), std::exp(x) - std::exp(-1.0), 1e-15) << x;
}

TEST(Chebyshev, UnderResolvedFunctionIsFlagged) {
  // 40 oscillations on 33 points cannot be resolved.
  auto c = coefficients_of([](double x) { return std::cos(40 * x); }, 33);
  EXPECT_FALSE(chebyshev_accuracy(c).resolved);
}

TEST(Chebyshev, ErrorEstimateBoundsTheTrueErrorOnAResolvedFunction) {
  // Just resolved: the estimate must not undercut the actual interpolation error.
  for (double w : {4.0, 8.0, 12.0, 16.0}) {
    const ChebyshevRule& rule = ChebyshevRule::get(33);
    std::vector<double> values(33), c(33);
    for (int j = 0; j < 33; ++j) values[j] = std::cos(w * rule.node(j) + 0.3);
    rule.coefficients(values, c);
    const ChebyshevAccuracy acc = chebyshev_accuracy(c);
    double worst = 0;
    for (double x = -1; x <= 1; x += 1e-3)
      worst = std::max(worst, std::abs(chebyshev_evaluate(c, x) - std::cos(w * x + 0.3)));
    if (acc.resolved) {
      EXPECT_LE(worst, acc.error) << "w = " << w;
    }
  }
}

}  // namespace
}  // namespace vrv
