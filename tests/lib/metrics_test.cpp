#include "lib/metrics.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace vrv {
namespace {

TEST(ErrorStats, KnownValues) {
  std::vector<double> e;
  for (int i = 1; i <= 100; ++i) e.push_back(i % 2 ? -0.01 * i : 0.01 * i);  // |e| = 0.01 .. 1.00
  const ErrorStats s = error_stats(e, 0.5);
  EXPECT_EQ(s.count, 100);
  EXPECT_DOUBLE_EQ(s.max, 1.0);
  EXPECT_NEAR(s.mean, 0.505, 1e-12);
  EXPECT_NEAR(s.rms, std::sqrt(338350.0 / 100) * 0.01, 1e-12);  // sum i^2 = 338350
  EXPECT_DOUBLE_EQ(s.p99, 0.99);                                 // 99th of 100 by nearest rank
  EXPECT_DOUBLE_EQ(s.fraction_over, 0.5);                        // 0.51 .. 1.00
  EXPECT_NEAR(s.mean_signed, 0.005, 1e-12);
}

TEST(ErrorStats, RefusesNaNAndHandlesEmpty) {
  EXPECT_THROW(error_stats(std::vector<double>{0.1, NAN}, 1), std::invalid_argument);
  EXPECT_EQ(error_stats(std::vector<double>{}, 1).count, 0);
}

// One at a time, the same sums as error_stats (all but p99), in the same order: the same bits.
TEST(ErrorStats, SumsOneAtATimeMatchErrorStats) {
  const std::vector<double> e{0.3, -1e-7, 2.5, -0.75, 1.0 / 3};
  ErrorSums sums(0.5);
  for (double x : e) sums.add(x);
  const ErrorStats a = sums.stats(), b = error_stats(e, 0.5);
  EXPECT_EQ(a.count, b.count);
  EXPECT_EQ(a.max, b.max);
  EXPECT_EQ(a.mean, b.mean);
  EXPECT_EQ(a.rms, b.rms);
  EXPECT_EQ(a.fraction_over, b.fraction_over);
  EXPECT_EQ(a.mean_signed, b.mean_signed);
  EXPECT_EQ(a.p99, 0);
  EXPECT_EQ(ErrorSums().stats().count, 0);
  ErrorSums with_nan;
  for (double x : {0.5, double(NAN), -2.0}) with_nan.add(x);
  EXPECT_EQ(with_nan.stats().max, 2.0);  // NaN leaves the max alone
  EXPECT_TRUE(std::isnan(with_nan.stats().mean));
}

TEST(FitOrder, ExactPowerLawHasNoSpread) {
  const std::vector<double> h{0.4, 0.2, 0.1, 0.05};
  std::vector<double> e;
  for (double x : h) e.push_back(3 * x * x);
  const OrderEstimate f = fit_order(h, e);
  EXPECT_NEAR(f.order, 2, 1e-12);
  EXPECT_NEAR(f.standard_error, 0, 1e-12);
  EXPECT_EQ(f.points, 4);
}

TEST(FitOrder, StandardErrorMatchesTheTextbookFormula) {
  const std::vector<double> h{1, 0.5, 0.25};
  const std::vector<double> e{1, 0.3, 0.05};
  const OrderEstimate f = fit_order(h, e);
  // By hand: x = log h, y = log e; b = Sxy / Sxx; se = sqrt(SSR / (n - 2) / Sxx).
  double mx = 0, my = 0;
  for (int i = 0; i < 3; ++i) mx += std::log(h[i]) / 3, my += std::log(e[i]) / 3;
  double sxx = 0, sxy = 0;
  for (int i = 0; i < 3; ++i) sxx += std::pow(std::log(h[i]) - mx, 2), sxy += (std::log(h[i]) - mx) * (std::log(e[i]) - my);
  const double b = sxy / sxx, a = my - b * mx;
  double ssr = 0;
  for (int i = 0; i < 3; ++i) ssr += std::pow(std::log(e[i]) - a - b * std::log(h[i]), 2);
  EXPECT_NEAR(f.order, b, 1e-12);
  EXPECT_NEAR(f.standard_error, std::sqrt(ssr / 1 / sxx), 1e-12);
  EXPECT_GT(f.standard_error, 0.1);
}

TEST(FitOrder, TwoPointsHaveNoStandardError) {
  const OrderEstimate f = fit_order(std::vector<double>{0.2, 0.1}, std::vector<double>{4e-2, 1e-2});
  EXPECT_NEAR(f.order, 2, 1e-12);
  EXPECT_TRUE(std::isnan(f.standard_error));
  EXPECT_TRUE(std::isnan(fit_order(std::vector<double>{0.2}, std::vector<double>{1.0}).order));
}

TEST(SelfConvergence, RecoversTheOrderWithUnevenRatios) {
  // I(h) = I + C h^p with uneven refinement: differences alone give p.
  const double p = 1.7, C = 0.3;
  const std::vector<double> h{0.3, 0.2, 0.07, 0.05, 0.02};
  std::vector<double> d;
  for (std::size_t k = 0; k + 1 < h.size(); ++k) d.push_back(C * (std::pow(h[k], p) - std::pow(h[k + 1], p)));
  const OrderEstimate f = self_convergence_order(h, d);
  EXPECT_NEAR(f.order, p, 1e-9);
  EXPECT_NEAR(f.standard_error, 0, 1e-8);
}

TEST(Judge, Verdicts) {
  const std::vector<double> h{0.4, 0.2, 0.1, 0.05};
  auto verdict = [&](std::vector<double> e, std::optional<double> K) {
    return judge(h, e, fit_order(h, e), JudgeOptions{K}).verdict;
  };
  EXPECT_EQ(verdict({16e-4, 4e-4, 1e-4, 0.25e-4}, 2.0), Verdict::converges);
  EXPECT_EQ(verdict({8e-3, 4e-3, 2e-3, 1e-3}, 2.0), Verdict::converges_lower);
  EXPECT_EQ(verdict({8e-3, 4e-3, 2e-3, 1e-3}, std::nullopt), Verdict::converges);
  EXPECT_EQ(verdict({16e-4, 4e-4, 1.1e-4, 1.0e-4}, 2.0), Verdict::stalls);
  EXPECT_EQ(verdict({1e-3, 1.01e-3, 0.99e-3, 1e-3}, std::nullopt), Verdict::stalls);
  EXPECT_EQ(verdict({1e-3, 2e-3, 4e-3, 8e-3}, 2.0), Verdict::diverges);
  const Judgement j = judge(h, std::vector<double>{16e-4, 4e-4, 1.1e-4, 1.0e-4},
                            fit_order(h, std::vector<double>{16e-4, 4e-4, 1.1e-4, 1.0e-4}), JudgeOptions{2.0});
  EXPECT_DOUBLE_EQ(j.floor, 1.0e-4);
}

TEST(Metrics, ObservedOrderIsTheLeastSquaresSlope) {
  // fit_order is order_estimate's fit of the points with a logarithm: an exact zero is left out.
  const std::vector<double> h{0.1, 0.05, 0.025}, e{3e-2, 7.5e-3, 1.875e-3};
  EXPECT_EQ(fit_order(h, e).order, estimate_order(h, e).order);
  EXPECT_EQ(fit_order(h, e).standard_error, estimate_order(h, e).standard_error);
  const OrderEstimate zero = fit_order(h, std::vector<double>{3e-2, 7.5e-3, 0});
  EXPECT_NEAR(zero.order, 2, 1e-12);
  EXPECT_EQ(zero.points, 2);
  EXPECT_TRUE(std::isnan(fit_order(std::vector<double>{0.1, 0.05}, std::vector<double>{1e-3, 0}).order));
}

TEST(Judge, LowerOnlyOutsideTheFitsBand) {
  const std::vector<double> h{0.4, 0.2, 0.1, 0.05};
  const auto judged = [&](const std::vector<double>& e) { return judge(h, e, fit_order(h, e), JudgeOptions{2.0}); };
  // One power law of order 1.7: no spread, so the band is the tolerance 0.25 and 1.7 is lower.
  std::vector<double> clean;
  for (double x : h) clean.push_back(std::pow(x, 1.7));
  EXPECT_EQ(judged(clean).verdict, Verdict::converges_lower);
  // Local orders 2.0, 1.2, 1.9 (overall 1.65): the points bend, the band max(2 c_1 SE, 0.25) ~ 1.03
  // reaches past 1.65, so the fit cannot call it lower: undetermined, which still fails an
  // expected order.
  const std::vector<double> bent{1.6e-3, 4e-4, 4e-4 * std::pow(2.0, -1.2), 4e-4 * std::pow(2.0, -3.1)};
  const OrderEstimate f = fit_order(h, bent);
  ASSERT_NEAR(f.order, 1.65, 1e-9);
  ASSERT_GT(order_tolerance(f, OrderTolerance{2, 0.25}), 2 - f.order);
  EXPECT_EQ(judged(bent).verdict, Verdict::undetermined) << judged(bent).reason;
  // Two points have no spread: the tolerance alone.
  const std::vector<double> h2{0.2, 0.1}, lower{4e-2, 1.2e-2}, near{4e-2, 1.1e-2};  // orders 1.74, 1.86
  EXPECT_EQ(judge(h2, lower, fit_order(h2, lower), JudgeOptions{2.0}).verdict, Verdict::converges_lower);
  EXPECT_EQ(judge(h2, near, fit_order(h2, near), JudgeOptions{2.0}).verdict, Verdict::converges);
}

}  // namespace
}  // namespace vrv
