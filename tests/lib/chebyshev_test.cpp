#include "lib/chebyshev.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "lib/ray_panel.h"

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
  // Just resolved: the estimate must not undercut the actual interpolation error.  Every case is
  // resolved: the coefficients of cos(w x + 0.3) are 2 J_k(w) up to sign, which fall
  // super-exponentially once k > w, and w <= 16 leaves half of the 33 coefficients to show it.
  for (double w : {4.0, 8.0, 12.0, 16.0}) {
    const ChebyshevRule& rule = ChebyshevRule::get(33);
    std::vector<double> values(33), c(33);
    for (int j = 0; j < 33; ++j) values[j] = std::cos(w * rule.node(j) + 0.3);
    rule.coefficients(values, c);
    const ChebyshevAccuracy acc = chebyshev_accuracy(c);
    double worst = 0;
    for (double x = -1; x <= 1; x += 1e-3)
      worst = std::max(worst, std::abs(chebyshev_evaluate(c, x) - std::cos(w * x + 0.3)));
    ASSERT_TRUE(acc.resolved) << "w = " << w;
    EXPECT_LE(worst, acc.error) << "w = " << w;
  }
}

// The speed changes of issue 10 must leave every value bitwise unchanged: the multi-point
// Clenshaw pass against the one-point recurrence (the old code path), and skipping the crossing
// search (may_cross false) only where find_crossings finds nothing.
TEST(Chebyshev, ManyPointEvaluationIsBitwiseTheOnePointRecurrence) {
  std::mt19937_64 rng(10);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int n : {1, 2, 3, 4, 7, 8, 9, 17, 33, 67, 129})
    for (int points : {1, 3, 8, 9, 33, 67}) {
      std::vector<double> c(n), x(points), out(points);
      for (int k = 0; k < n; ++k) c[k] = u(rng) * std::pow(0.7, k);
      for (double& xi : x) xi = u(rng);
      x[0] = -1;
      chebyshev_evaluate_many(c, x, out);
      for (int i = 0; i < points; ++i)
        EXPECT_EQ(std::bit_cast<std::uint64_t>(out[i]), std::bit_cast<std::uint64_t>(chebyshev_evaluate(c, x[i])))
            << n << " " << points << " " << i;
    }
}

// The rule's products are unrolled for the hot paths' sizes (4, 9, 17, 33): each row's sum must
// still run over the columns in order from 0, as for every other size, so values do not move.
TEST(Chebyshev, FixedSizeProductsAreBitwiseTheColumnOrderSum) {
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int n : {2, 3, 4, 5, 8, 9, 10, 16, 17, 18, 32, 33, 34, 65}) {
    const ChebyshevRule& rule = ChebyshevRule::get(n);
    // The matrices' columns, from unit vectors (a product with e_j is exact: one term).
    std::vector<std::vector<double>> to_c(n, std::vector<double>(n)), cum(n, std::vector<double>(n));
    for (int j = 0; j < n; ++j) {
      std::vector<double> e(n, 0.0);
      e[j] = 1;
      rule.coefficients(e, to_c[j]);
      rule.cumulative_integral(e, cum[j]);
    }
    std::vector<double> x(n), c(n), q(n);
    for (double& xi : x) xi = u(rng) * std::exp(4 * u(rng));
    rule.coefficients(x, c);
    rule.cumulative_integral(x, q);
    for (int k = 0; k < n; ++k) {
      double sum_c = 0, sum_q = 0;
      for (int j = 0; j < n; ++j) sum_c += to_c[j][k] * x[j], sum_q += cum[j][k] * x[j];
      EXPECT_EQ(std::bit_cast<std::uint64_t>(c[k]), std::bit_cast<std::uint64_t>(sum_c)) << n << " " << k;
      EXPECT_EQ(std::bit_cast<std::uint64_t>(q[k]), std::bit_cast<std::uint64_t>(sum_q)) << n << " " << k;
    }
  }
}

TEST(Chebyshev, CrossingSearchIsSkippedOnlyWhereItFindsNothing) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  const std::vector<double> levels{-0.9, -0.3, 0.1, 0.5, 0.55, 1.2};
  int skipped = 0, searched = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const int n = trial % 3 == 0 ? 4 : 33;
    RayPanel panel{0.5, 1.75, std::vector<double>(n), std::vector<double>(n), 0, 0, true};
    const double decay = 0.2 + 0.6 * (u(rng) + 1) / 2, scale = std::pow(10.0, 3 * u(rng) - 1);
    for (int k = 0; k < n; ++k) panel.coefficients[k] = (k == 0 ? 1.5 * u(rng) : scale * u(rng)) * std::pow(decay, k);
    std::vector<Crossing> found;
    find_crossings(panel, levels, found);
    if (!may_cross(panel, levels)) {
      ++skipped;
      EXPECT_TRUE(found.empty()) << trial;
    } else {
      ++searched;
    }
  }
  EXPECT_GT(skipped, 400);  // the skip is exercised
  EXPECT_GT(searched, 400);
}

}  // namespace
}  // namespace vrv
