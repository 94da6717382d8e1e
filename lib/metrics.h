#pragma once
// Image error statistics and convergence orders, the numbers `vrv verify` reports and gates on.
//
//  - error_stats: max, mean, RMS and 99th percentile of |e|, the fraction of values with
//    |e| > threshold, and the signed mean, over one set of per-pixel errors;
//  - fit_order: the observed order p of error ~ C h^p, lib/order_estimate.h's fit (the
//    least-squares slope of log(error) against log(h), its standard error and bias factor) of the
//    points that have a logarithm;
//  - self_convergence_order: the same order from differences between successive images alone
//    (Etiene et al., "Verifying volume rendering using discretization error analysis", TVCG
//    2014): no reference is needed;
//  - judge: a verdict (converges, converges at a lower order, stalls at a floor, diverges; lower
//    only outside order_estimate's band around the expected order).
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "lib/order_estimate.h"

namespace vrv {

struct ErrorStats {
  long count = 0;            // values summarised
  double max = 0;            // max |e|
  double mean = 0;           // mean |e|
  double rms = 0;            // sqrt(mean e^2)
  double p99 = 0;            // 99th percentile of |e| (nearest rank: the ceil(0.99 n)-th smallest)
  double fraction_over = 0;  // fraction of values with |e| > threshold, in [0, 1]
  double mean_signed = 0;    // mean e (a bias shows here)
};

// Statistics of `errors`; every value must be finite (std::invalid_argument otherwise, naming
// the index).  An empty span gives count 0 and zeros.
ErrorStats error_stats(std::span<const double> errors, double threshold);

// The same sums taken one error at a time, in the order given, without keeping the errors: for
// a caller that cannot afford a copy of its pixels (render) or skips some of them (the sampling
// study's missed rays).  stats() leaves p99 at 0, which needs every value.  A NaN error is not
// refused here: it leaves max as it was and makes mean, rms and mean_signed NaN.
class ErrorSums {
 public:
  explicit ErrorSums(double threshold = 0) : threshold_(threshold) {}
  void add(double e);
  ErrorStats stats() const;

 private:
  double threshold_;
  ErrorStats s_;
  double sum_abs_ = 0, sum_sq_ = 0, sum_ = 0;
  long over_ = 0;
};

// Which statistic an order fit or a bound reads.
enum class Metric { max, mean, rms, p99, fraction_over };
std::string_view metric_name(Metric m);                   // "max", "mean", "rms", "p99", "fraction_over"
std::optional<Metric> parse_metric(std::string_view name);
double metric_value(const ErrorStats& s, Metric m);

// estimate_order of the points with a positive, finite error and step: the others are left out (an
// error of exactly 0 has no logarithm).  NaN order with fewer than two such points.
OrderEstimate fit_order(std::span<const double> steps, std::span<const double> errors);

// Self-convergence: images at steps h_0 > h_1 > ... (sorted here, with their differences given
// in the same order as the steps they start from: differences[k] = ||I(h_k) - I(h_{k+1})|| for
// the k-th largest step).  With I(h) = I + C h^p, d_k = C h_k^p (1 - (h_{k+1}/h_k)^p); the factor
// in brackets depends on p when the step ratio varies, so the fit is repeated with it divided
// out until p settles (for a constant ratio the first fit is already exact).  Needs two
// differences (three images) for an order, three for its standard error.
// `steps` has one more entry than `differences`.
OrderEstimate self_convergence_order(std::span<const double> steps, std::span<const double> differences);

enum class Verdict { converges, converges_lower, stalls, diverges, undetermined };
std::string_view verdict_name(Verdict v);  // "converges", "converges at a lower order", ...

struct JudgeOptions {
  std::optional<double> expected_order;  // K; without it any positive order converges
  double tolerance = 0.25;  // observed >= K - tolerance converges at K; |order| < tolerance is no order
  // "Lower" is claimed only below K - max(margin * c_1 * SE, tolerance), order_estimate's band
  // (lib/order_estimate.h; two points have no spread: the tolerance alone): points that bend away
  // from one power law cannot place the order closer than that, so between the two it is
  // undetermined (the same band the studies check their orders in).
  double margin = 2;
  double stall_fraction = 0.5;
};

struct Judgement {
  Verdict verdict = Verdict::undetermined;
  std::string reason;  // one sentence with the numbers
  double floor = 0;    // stalls: the error where it stalls; NaN otherwise
};

// steps and errors in any order (sorted here by decreasing step); fit = fit_order of them.
Judgement judge(std::span<const double> steps, std::span<const double> errors, const OrderEstimate& fit,
                const JudgeOptions& options);

// Severity for combining verdicts (diverges > stalls > converges_lower > undetermined > converges).
int severity(Verdict v);

}  // namespace vrv
