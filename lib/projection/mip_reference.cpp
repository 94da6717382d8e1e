#include "lib/projection/mip_reference.h"

#include <algorithm>
#include <cmath>

#include "lib/chebyshev.h"

namespace vrv::projection_detail {
namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();
constexpr double kFieldShare = 0.5;

}  // namespace

void extremum_breaks(const RayPanel& panel, std::vector<double>& out) {
  const int n = panel.size();
  if (n > 4) {
    monotone_breaks(panel, out);
    return;
  }
  out.push_back(panel.a);
  if (n >= 3) {
    // p'(x) = d0 + d1 x + d2 T2(x) = (d0 - d2) + d1 x + 2 d2 x^2 on [-1, 1].
    double d[4] = {0, 0, 0, 0};
    chebyshev_derivative(panel.coefficients, {d, static_cast<std::size_t>(n)});
    // Scaled by a power of two (exactly; the roots stay), so that B^2 - 4AC neither underflows nor
    // overflows: a cell of values near 1e-200 lost its maximum to an underflowed discriminant.
    int exponent = 0;
    std::frexp(std::max({std::abs(d[0]), std::abs(d[1]), std::abs(d[2])}), &exponent);
    for (double& x : d) x = std::ldexp(x, -exponent);
    const double A = 2 * d[2], B = d[1], C = d[0] - d[2];
    double roots[2];
    int count = 0;
    if (A == 0) {
      if (B != 0) roots[count++] = -C / B;
    } else {
      const double disc = B * B - 4 * A * C;
      if (disc >= 0) {
        // The stable pair: no cancellation between -B and the square root.
        const double q = -0.5 * (B + std::copysign(std::sqrt(disc), B));
        if (q != 0) roots[count++] = q / A, roots[count++] = C / q;
        else roots[count++] = 0;
      }
    }
    std::sort(roots, roots + count);
    for (int i = 0; i < count; ++i) {
      if (!(roots[i] > -1 && roots[i] < 1)) continue;
      const double t = panel.t_of(roots[i]);
      if (t > out.back() && t < panel.b) out.push_back(t);
    }
  }
  out.push_back(panel.b);
}

MipAccumulator::MipAccumulator(const TransferFunction* classify, double tol) : tf_(classify), tol_(tol) {
  if (tf_) slope_ = tf_->max_extinction_slope();
}

double MipAccumulator::field_tolerance() const {
  return slope_ > 0 ? kFieldShare * tol_ / slope_ : std::numeric_limits<double>::infinity();
}

const PiecewiseLinear& MipAccumulator::curve() const {
  return tf_->convention() == Convention::emission_extinction ? tf_->second() : tf_->first();
}

double MipAccumulator::mapped(double y) const {
  const double a = std::max(0.0, y);
  if (tf_->convention() == Convention::emission_extinction) return a;
  return -std::log1p(-a) / tf_->unit_length();
}

double MipAccumulator::sup_over(double lo, double hi) const {
  // A piecewise-linear curve's supremum over [lo, hi]: its values at both ends, and at every
  // control point in (lo, hi] (both sides of a jump there: the values below it are reached).
  const PiecewiseLinear& c = curve();
  double y = std::max(c(lo), c(hi));
  for (const ControlPoint& p : c.points())
    if (p.v > lo && p.v <= hi) y = std::max(y, p.y);
  return mapped(y);
}

double MipAccumulator::inf_over(double lo, double hi) const {
  const PiecewiseLinear& c = curve();
  double y = std::min(c(lo), c(hi));
  for (const ControlPoint& p : c.points())
    if (p.v > lo && p.v <= hi) y = std::min(y, p.y);
  return mapped(y);
}

void MipAccumulator::add(const RayPanel& panel, std::vector<MipCandidate>& candidates, double p_min,
                         double p_max, double field_error) {
  std::sort(candidates.begin(), candidates.end(),
            [](const MipCandidate& x, const MipCandidate& y) { return x.t < y.t; });
  const std::size_t index = panels_.size();
  PanelBound bound;
  const double noise = panel.noise + 2 * eps * std::max(std::abs(p_min), std::abs(p_max));
  if (!tf_) {
    bound.upper = p_max + field_error;
    bound.tie = noise;
    bound.lower = -INFINITY;  // set below: the largest value found, less its rounding
    for (const MipCandidate& c : candidates) {
      bound.attained = std::max(bound.attained, c.value);
      entries_.push_back({c.t, c.value, field_error, noise, index});
    }
    bound.upper = std::max(bound.upper, bound.attained);
    bound.lower = bound.attained - noise;
    panels_.push_back(bound);
    return;
  }
  // Classified: the field reaches every value between its smallest and largest found on the
  // panel (it is continuous on a panel), each computed value within its rounding of the truth.
  double lo = INFINITY, hi = -INFINITY;
  for (const MipCandidate& c : candidates)
    if (!c.crossing) lo = std::min(lo, c.value), hi = std::max(hi, c.value);
  // Reported: the supremum over the values found.  Certain: over the range the field surely
  // reaches (shrunk by its rounding), or where that is empty (a field flat to within its rounding,
  // perhaps at a jump's level) the least tau can be there.
  bound.attained = sup_over(lo, hi);
  const double reach_lo = lo + noise, reach_hi = hi - noise;
  bound.lower = reach_lo <= reach_hi ? sup_over(reach_lo, reach_hi) : inf_over(lo - noise, hi + noise);
  bound.upper = std::max(sup_over(p_min - field_error, p_max + field_error), bound.attained);
  bound.tie = slope_ * noise;
  for (const MipCandidate& c : candidates) {
    if (c.crossing && !(c.value >= lo && c.value <= hi)) continue;
    double q = sup_over(c.value, c.value);
    if (c.crossing)  // the field passes the level: both sides of a jump there are reached
      for (const ControlPoint& p : curve().points())
        if (p.v == c.value) q = std::max(q, mapped(p.y));
    entries_.push_back({c.t, q, bound.upper - bound.attained, bound.tie, index});
  }
  panels_.push_back(bound);
}

MipAccumulator::Outcome MipAccumulator::finish() const {
  Outcome out;
  if (panels_.empty()) return out;
  out.any = true;
  double upper = -INFINITY, lower = -INFINITY, value = -INFINITY;
  std::size_t best = 0;
  for (std::size_t i = 0; i < panels_.size(); ++i) {
    upper = std::max(upper, panels_[i].upper);
    lower = std::max(lower, panels_[i].lower);
    if (panels_[i].attained > value) value = panels_[i].attained, best = i;
  }
  const double tie = panels_[best].tie + 2 * eps * std::abs(value);
  out.value = value;
  // The truth lies in [lower, upper].
  out.estimate = std::max({upper - value, value - lower, tie}) + 2 * eps * std::abs(value);
  // The first place that reaches the value within the rounding (a plateau: its start).
  std::size_t first = entries_.size();
  for (std::size_t k = 0; k < entries_.size(); ++k)
    if (entries_[k].q >= value - tie && panels_[entries_[k].panel].attained >= value - tie) {
      first = k;
      break;
    }
  if (first == entries_.size()) {  // a supremum between candidates: the best panel's start
    for (std::size_t k = 0; k < entries_.size(); ++k)
      if (entries_[k].panel == best) {
        first = k;
        break;
      }
  }
  out.position = entries_[first].t;
  if (tf_) return out;
  // Ambiguous: another maximum, separated from this one by a dip deeper than twice the estimate,
  // that may reach the value within the estimate.
  const auto separate = [&](std::size_t from, std::size_t to) {
    double dip = INFINITY;
    for (std::size_t k = std::min(from, to) + 1; k < std::max(from, to); ++k) dip = std::min(dip, entries_[k].q);
    return dip < entries_[to].q - 2 * out.estimate;
  };
  for (std::size_t k = 0; k < entries_.size() && !out.ambiguous; ++k) {
    const Entry& e = entries_[k];
    if (k == first || e.q >= value - tie) continue;
    if (e.q + e.err >= value - out.estimate && separate(first, k)) out.ambiguous = true;
  }
  return out;
}

}  // namespace vrv::projection_detail
