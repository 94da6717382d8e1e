#include "lib/metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "lib/util/enum_names.h"
#include "lib/util/not_a_number.h"

namespace vrv {
namespace {

struct Point {
  double h, e;
};

// (step, error) pairs sorted by decreasing step.
std::vector<Point> sorted_points(std::span<const double> steps, std::span<const double> errors) {
  if (steps.size() != errors.size())
    throw std::invalid_argument("order fit: steps and errors differ in number");
  std::vector<Point> p;
  for (std::size_t i = 0; i < steps.size(); ++i) p.push_back({steps[i], errors[i]});
  std::sort(p.begin(), p.end(), [](const Point& a, const Point& b) { return a.h > b.h; });
  return p;
}

bool usable(double h, double e) { return h > 0 && std::isfinite(h) && e > 0 && std::isfinite(e); }

// order_tolerance's band with the judge's tolerance as its floor; two points have no spread to
// derive it from, so the tolerance alone.
double order_band(const OrderEstimate& fit, const JudgeOptions& options) {
  const double band = order_tolerance(fit, OrderTolerance{options.margin, options.tolerance});
  return std::isnan(band) ? options.tolerance : band;
}

}  // namespace

void ErrorSums::add(double e) {
  const double a = std::abs(e);
  s_.max = std::max(s_.max, a);
  sum_abs_ += a;
  sum_sq_ += e * e;
  sum_ += e;
  over_ += a > threshold_;
  ++s_.count;
}

ErrorStats ErrorSums::stats() const {
  ErrorStats s = s_;
  if (s.count == 0) return s;
  const double n = static_cast<double>(s.count);
  s.mean = sum_abs_ / n;
  s.rms = std::sqrt(sum_sq_ / n);
  s.mean_signed = sum_ / n;
  s.fraction_over = static_cast<double>(over_) / n;
  return s;
}

ErrorStats error_stats(std::span<const double> errors, double threshold) {
  ErrorSums sums(threshold);
  std::vector<double> abs(errors.size());
  for (std::size_t i = 0; i < errors.size(); ++i) {
    if (!std::isfinite(errors[i])) throw std::invalid_argument(fmt::format("error {} is {}", i, errors[i]));
    sums.add(errors[i]);
    abs[i] = std::abs(errors[i]);
  }
  ErrorStats s = sums.stats();
  if (errors.empty()) return s;
  const auto rank = static_cast<std::size_t>(std::ceil(0.99 * static_cast<double>(errors.size()))) - 1;  // nearest rank, 0-based
  std::nth_element(abs.begin(), abs.begin() + static_cast<std::ptrdiff_t>(rank), abs.end());
  s.p99 = abs[rank];
  return s;
}

namespace {

constexpr NameTable<Metric, 5> kMetrics{{{Metric::max, "max"},
                                         {Metric::mean, "mean"},
                                         {Metric::rms, "rms"},
                                         {Metric::p99, "p99"},
                                         {Metric::fraction_over, "fraction_over"}}};
static_assert(names_complete(kMetrics));

}  // namespace

std::string_view metric_name(Metric m) { return name_of(kMetrics, m); }
std::optional<Metric> parse_metric(std::string_view name) { return parse_name(kMetrics, name); }

double metric_value(const ErrorStats& s, Metric m) {
  switch (m) {
    case Metric::max: return s.max;
    case Metric::mean: return s.mean;
    case Metric::rms: return s.rms;
    case Metric::p99: return s.p99;
    case Metric::fraction_over: return s.fraction_over;
  }
  return kNaN;
}

OrderEstimate fit_order(std::span<const double> steps, std::span<const double> errors) {
  std::vector<double> h, e;
  for (const Point& p : sorted_points(steps, errors))
    if (usable(p.h, p.e)) h.push_back(p.h), e.push_back(p.e);
  return estimate_order(h, e);
}

OrderEstimate self_convergence_order(std::span<const double> steps, std::span<const double> differences) {
  if (steps.size() != differences.size() + 1)
    throw std::invalid_argument("self-convergence: need one more step than differences");
  std::vector<double> h(steps.begin(), steps.end());
  std::sort(h.begin(), h.end(), std::greater<>());
  std::vector<double> x, y, ratio;  // ratio: h_{k+1} / h_k
  for (std::size_t k = 0; k < differences.size(); ++k) {
    if (!usable(h[k], differences[k]) || !(h[k + 1] > 0) || !(h[k + 1] < h[k])) continue;
    x.push_back(std::log(h[k]));
    y.push_back(std::log(differences[k]));
    ratio.push_back(h[k + 1] / h[k]);
  }
  OrderEstimate f = estimate_log_order(x, y);
  // Divide out (1 - r^p): fixed-point iteration on p, a contraction for the ratios used here.
  for (int it = 0; it < 50 && std::isfinite(f.order) && f.order > 0; ++it) {
    std::vector<double> yc(y.size());
    for (std::size_t k = 0; k < y.size(); ++k) yc[k] = y[k] - std::log1p(-std::pow(ratio[k], f.order));
    const OrderEstimate next = estimate_log_order(x, yc);
    const bool settled = std::abs(next.order - f.order) <= 1e-12 * std::max(1.0, std::abs(f.order));
    f = next;
    if (settled) break;
  }
  return f;
}

std::string_view verdict_name(Verdict v) {
  switch (v) {
    case Verdict::converges: return "converges";
    case Verdict::converges_lower: return "converges at a lower order";
    case Verdict::stalls: return "stalls at a floor";
    case Verdict::diverges: return "diverges";
    case Verdict::undetermined: return "undetermined";
  }
  return "?";
}

int severity(Verdict v) {
  switch (v) {
    case Verdict::converges: return 0;
    case Verdict::undetermined: return 1;
    case Verdict::converges_lower: return 2;
    case Verdict::stalls: return 3;
    case Verdict::diverges: return 4;
  }
  return 5;
}

Judgement judge(std::span<const double> steps, std::span<const double> errors, const OrderEstimate& fit,
                const JudgeOptions& options) {
  std::vector<Point> p;
  for (const Point& q : sorted_points(steps, errors))
    if (usable(q.h, q.e)) p.push_back(q);
  Judgement j{Verdict::undetermined, "", kNaN};
  if (p.size() < 2 || !std::isfinite(fit.order)) {
    j.reason = fmt::format("{} usable point(s): no order", p.size());
    return j;
  }
  const double tol = options.tolerance;
  std::vector<double> local;  // slope between consecutive steps, coarse to fine
  for (std::size_t k = 0; k + 1 < p.size(); ++k)
    local.push_back(std::log(p[k].e / p[k + 1].e) / std::log(p[k].h / p[k + 1].h));
  if (fit.order < -tol) {
    j.verdict = Verdict::diverges;
    j.reason = fmt::format("the error grows as the step shrinks (order {:.3g}: {:.3g} at h = {:.3g}, "
                           "{:.3g} at h = {:.3g})", fit.order, p.front().e, p.front().h, p.back().e, p.back().h);
    return j;
  }
  const double earlier = local.size() >= 2 ? *std::max_element(local.begin(), local.end() - 1) : kNaN;
  if (std::abs(fit.order) < tol ||
      (local.size() >= 2 && earlier > tol && local.back() < options.stall_fraction * earlier)) {
    j.verdict = Verdict::stalls;
    j.floor = p.back().e;
    j.reason = fmt::format("the error stops falling at {:.3g} (local order {:.3g} between h = {:.3g} "
                           "and {:.3g}; overall {:.3g})", p.back().e, local.back(), p[p.size() - 2].h,
                           p.back().h, fit.order);
    return j;
  }
  if (options.expected_order && fit.order < *options.expected_order - tol) {
    const double band = order_band(fit, options);
    if (fit.order >= *options.expected_order - band) {  // undetermined
      j.reason = fmt::format("observed order {:.3g} below the expected {:.3g} by less than the fit's band {:.3g} "
                             "(standard error {:.2g}: the points bend away from one power law; finer steps "
                             "would tell)", fit.order, *options.expected_order, band, fit.standard_error);
      return j;
    }
    j.verdict = Verdict::converges_lower;
    j.reason = fmt::format("observed order {:.3g} below the expected {:.3g} (tolerance {:.3g})",
                           fit.order, *options.expected_order, tol);
    return j;
  }
  j.verdict = Verdict::converges;
  j.reason = options.expected_order
                 ? fmt::format("observed order {:.3g}, expected {:.3g} (tolerance {:.3g})", fit.order,
                               *options.expected_order, tol)
                 : fmt::format("observed order {:.3g}", fit.order);
  return j;
}

}  // namespace vrv
