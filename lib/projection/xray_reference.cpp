#include "lib/projection/xray_reference.h"

#include <algorithm>
#include <cmath>

#include "lib/chebyshev.h"

namespace vrv::projection_detail {
namespace {

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
// The tolerance is shared out: the field proxies' error, and the quadrature of tau(p).
constexpr double kProxyShare = 0.5;
constexpr double kQuadratureShare = 0.25;
constexpr int kMaxLevel = 40;

double max_abs(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

}  // namespace

XrayAccumulator::XrayAccumulator(const TransferFunction* classify, double tol, double length, double end_rounding)
    : tf_(classify), tol_(tol), length_(length), end_rounding_(end_rounding) {
  if (tf_)
    for (double v : tf_->breakpoints())
      if (tf_->jump_at(v).extinction != 0) jump_levels_.push_back(v);
}

double XrayAccumulator::field_tolerance() const {
  // int |f - p| <= length x the panels' error; through tau, times its largest slope.
  const double weight = length_ * (tf_ ? tf_->max_extinction_slope() : 1.0);
  return weight > 0 ? kProxyShare * tol_ / weight : std::numeric_limits<double>::infinity();
}

// Neumaier's compensated sum (a few lines; none of the project's libraries offers one): a ray of
// thousands of cells keeps the rounding of its sum at a few ulps of the total.
void XrayAccumulator::accumulate(double x) {
  const double s = value_ + x;
  compensation_ += std::abs(value_) >= std::abs(x) ? (value_ - s) + x : (x - s) + value_;
  value_ = s;
  sum_abs_ += std::abs(x);
}

double XrayAccumulator::integrand_bound(double v) const {
  if (!tf_) return std::abs(v);
  const double tau = tf_->extinction(v);
  return tau + tf_->jump_at(v).extinction;
}

void XrayAccumulator::add(const RayPanel& panel, double moved) {
  // The chord's ends (the Lobatto nodes hold both: values[n - 1] at a, values[0] at b).
  const int n = panel.size();
  if (first_) error_ += end_rounding_ * (integrand_bound(panel.values[n - 1]) + panel.noise), first_ = false;
  last_end_ = integrand_bound(panel.values[0]) + panel.noise;
  // The proxy interpolates the computed values: its error, the values' own rounding, and the
  // far-origin error of every position.
  const double field_error = panel.error + panel.noise + moved;
  if (!tf_) {
    const double half = 0.5 * (panel.b - panel.a);
    double coefficient_sum = 0;
    for (double c : panel.coefficients) coefficient_sum += std::abs(c);
    accumulate(half * chebyshev_integral(panel.coefficients));
    error_ += (panel.b - panel.a) * field_error + 4 * kEpsilon * panel.size() * half * coefficient_sum;
    return;
  }
  crossings_.clear();
  if (may_cross(panel, tf_->breakpoints())) find_crossings(panel, tf_->breakpoints(), crossings_);
  double c = panel.a;
  for (std::size_t k = 0; k <= crossings_.size(); ++k) {
    const double t = k < crossings_.size() ? crossings_[k].t : panel.b;
    if (t > c) add_piece(panel, c, t, field_error);
    c = std::max(c, t);
  }
  charge_jumps(panel, field_error);
}

void XrayAccumulator::add_piece(const RayPanel& panel, double c, double d, double field_error) {
  const TransferSegment seg = tf_->segment(panel(0.5 * (c + d)));
  accumulate(integrate_tau(panel, c, d, seg, 0));
  // |tau(f) - tau(p)| <= max |dtau/dv| |f - p|, whichever branch f is on.
  const double slope = tf_->max_extinction_slope();
  if (slope > 0 && field_error > 0) error_ += (d - c) * field_error * slope;
}

double XrayAccumulator::integrate_tau(const RayPanel& panel, double c, double d, const TransferSegment& seg,
                                      int level) {
  // Affine tau of the proxy is a polynomial of the proxy's degree: its own number of
  // Clenshaw-Curtis points integrate it exactly.  Otherwise 17, 33, 65 points, then halves.
  const bool exact = tf_->affine();
  const double half = 0.5 * (d - c), mid = 0.5 * (c + d);
  const double local_tol = kQuadratureShare * tol_ * (d - c) / std::max(length_, d - c);
  const double slope = tf_->max_extinction_slope();
  for (int n : exact ? std::vector<int>{std::max(panel.size(), 1)} : std::vector<int>{17, 33, 65}) {
    const ChebyshevRule& rule = ChebyshevRule::get(n);
    std::vector<double> xs(n), v(n), tau(n), coefficients(n);
    for (int j = 0; j < n; ++j) xs[j] = panel.x_of(mid + half * rule.node(j));
    chebyshev_evaluate_many(panel.coefficients, xs, v);
    for (int j = 0; j < n; ++j) tau[j] = seg.tau(v[j]);
    rule.coefficients(tau, coefficients);
    // Each node's rounding: of tau itself, and of v through tau's slope.
    const double noise = 8 * kEpsilon * (max_abs(tau) + slope * max_abs(v));
    const ChebyshevAccuracy acc = chebyshev_accuracy(coefficients, noise);
    const double rounding = (d - c) * noise;
    const double quadrature = exact ? 0.0 : 2 * half * acc.error;
    if (exact || (acc.resolved && (quadrature <= local_tol || acc.at_rounding)) ||
        (n == 65 && !(level < kMaxLevel && mid > c && mid < d))) {
      error_ += quadrature + rounding;
      return half * chebyshev_integral(coefficients);
    }
  }
  return integrate_tau(panel, c, mid, seg, level + 1) + integrate_tau(panel, mid, d, seg, level + 1);
}

void XrayAccumulator::charge_jumps(const RayPanel& panel, double field_error) {
  if (jump_levels_.empty()) return;
  breaks_.clear();
  monotone_breaks(panel, breaks_);
  for (std::size_t i = 0; i + 1 < breaks_.size(); ++i)
    for (double level : jump_levels_) {
      // The field may cross the level anywhere in the band where the proxy is within its error
      // of it: there tau is off by the jump at most.
      const auto band = level_band(panel, breaks_[i], breaks_[i + 1], level,
                                   field_error + 4 * kEpsilon * std::abs(level));
      if (!band) continue;
      const double width = band->w - band->u + 4 * kEpsilon * std::max(std::abs(band->u), std::abs(band->w));
      error_ += tf_->jump_at(level).extinction * width;
    }
}

}  // namespace vrv::projection_detail
