#include "lib/order_estimate.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "lib/util/not_a_number.h"

namespace vrv {
namespace {

struct LineFit {
  double slope = kNaN, standard_error = kNaN;
};

// Ordinary least squares of y against x with centred sums (no cancellation in Sxx, Sxy).
LineFit fit_line(const std::vector<double>& x, const std::vector<double>& y) {
  const std::size_t n = x.size();
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < n; ++i) mx += x[i], my += y[i];
  mx /= static_cast<double>(n);
  my /= static_cast<double>(n);
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < n; ++i) sxx += (x[i] - mx) * (x[i] - mx), sxy += (x[i] - mx) * (y[i] - my);
  LineFit f;
  if (!(sxx > 0)) return f;
  f.slope = sxy / sxx;
  if (n < 3) return f;
  double rss = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = y[i] - my - f.slope * (x[i] - mx);
    rss += r * r;
  }
  f.standard_error = std::sqrt(rss / static_cast<double>(n - 2) / sxx);
  return f;
}

// x = log(step), y = log(error), h = step / largest step (the bias factor is scale-free, and
// this keeps the numbers near 1).
OrderEstimate fit(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& h) {
  const LineFit f = fit_line(x, y);
  const LineFit g = fit_line(x, h);  // the model's D h term, D = 1
  return {f.slope, f.standard_error, std::abs(g.slope) / g.standard_error, static_cast<long>(x.size())};
}

}  // namespace

OrderEstimate estimate_order(const std::vector<double>& steps, const std::vector<double>& errors) {
  OrderEstimate out{kNaN, kNaN, kNaN, static_cast<long>(steps.size())};
  if (steps.size() < 2 || steps.size() != errors.size()) return out;
  std::vector<double> x, y, h;
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const bool ok = std::isfinite(steps[i]) && steps[i] > 0 && std::isfinite(errors[i]) && errors[i] > 0;
    if (!ok) return out;
    x.push_back(std::log(steps[i]));
    y.push_back(std::log(errors[i]));
    h.push_back(steps[i] / *std::max_element(steps.begin(), steps.end()));
  }
  return fit(x, y, h);
}

OrderEstimate estimate_log_order(const std::vector<double>& log_steps, const std::vector<double>& log_errors) {
  if (log_steps.size() < 2 || log_steps.size() != log_errors.size())
    return {kNaN, kNaN, kNaN, static_cast<long>(log_steps.size())};
  const double largest = *std::max_element(log_steps.begin(), log_steps.end());
  std::vector<double> h;
  for (double x : log_steps) h.push_back(std::exp(x - largest));
  return fit(log_steps, log_errors, h);
}

double order_tolerance(const OrderEstimate& fit, const OrderTolerance& tolerance) {
  const double derived = tolerance.margin * fit.bias_factor * fit.standard_error;
  if (!std::isfinite(derived)) return kNaN;
  return std::max(derived, tolerance.floor);
}

bool order_matches(const OrderEstimate& fit, double expected, const OrderTolerance& tolerance) {
  return std::abs(fit.order - expected) <= order_tolerance(fit, tolerance);  // false on NaN
}

}  // namespace vrv
