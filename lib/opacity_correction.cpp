#include "lib/opacity_correction.h"

#include "lib/util/enum_names.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/Dense>
#include <boost/math/tools/toms748_solve.hpp>

namespace vrv {
namespace {

// Opacities outside [0, 1] are clamped; NaN (which fails both comparisons) becomes 0.
double clamp01(double a) { return a > 0 ? (a < 1 ? a : 1.0) : 0.0; }

void check_factor(int N) {
  if (N < 1) throw std::invalid_argument("oversampling factor N must be >= 1, got " + std::to_string(N));
}

// log(1 - x) for x = p * alpha in [0, 1].  At x = 1 the exact value is -inf; a finite stand-in
// below every other attainable value (log of the smallest subnormal) keeps F finite and
// monotone, so that the bracketing solver never interpolates through an infinity.
constexpr double kLogZero = -745.2;
double log_transparency(double x) { return x >= 1 ? kLogZero : std::log1p(-x); }

// Neumaier's compensated sum: the terms of F are of one sign except the target, so this keeps F
// accurate to a few ulps of |log target| even for N = 1024 terms.
struct CompensatedSum {
  double sum = 0, c = 0;
  void add(double x) {
    const double t = sum + x;
    c += std::fabs(sum) >= std::fabs(x) ? (sum - t) + x : (x - t) + sum;
    sum = t;
  }
  double value() const { return sum + c; }
};

// What a group aims at: log_target = log of the target transparency (<= 0, -inf for an opaque
// unit sample), transparency = exp(log_target), unit = 1 - transparency (the unit sample's opacity).
struct Target {
  double log_target;
  double transparency;
  double unit;
};

// Edge conventions shared by the exact solver and the quadratic fit; returns p if decided.
std::optional<double> decided_p(std::span<const double> alphas, const Target& t) {
  const bool any_positive = std::any_of(alphas.begin(), alphas.end(), [](double a) { return clamp01(a) > 0; });
  if (!any_positive) return 1.0;                    // every p solves it: keep the group as it is
  if (!(t.log_target < 0)) return 0.0;              // transparent unit sample: only p = 0
  if (t.log_target == -std::numeric_limits<double>::infinity()) return 1.0;  // opaque: p = 1
  return std::nullopt;
}

// F(p) = sum_k log1p(-p alpha_k) - log_target: decreasing and concave on [0, 1],
// F(0) = -log_target > 0.
double F_log(std::span<const double> alphas, double log_target, double p) {
  CompensatedSum s;
  s.add(-log_target);
  for (double a : alphas) s.add(log_transparency(p * clamp01(a)));
  return s.value();
}

double dF_log(std::span<const double> alphas, double p) {
  double d = 0;
  for (double a : alphas) {
    const double x = clamp01(a);
    d -= x / (1 - p * x);  // -inf at p x = 1
  }
  return d;
}

// TOMS 748 on a bracket [0, hi] with F(0) > 0 >= F(hi).  Because F is concave, the Newton step
// from 0, -log_target / sum alpha_k, lies right of the root and tightens hi when it is below 1.
double exact_p(std::span<const double> alphas, const Target& t) {
  if (auto p = decided_p(alphas, t)) return *p;
  const auto F = [&](double p) { return F_log(alphas, t.log_target, p); };
  const double f0 = F(0.0);  // = -log_target > 0
  double hi = 1, fhi = F(1.0);
  if (fhi >= 0) return 1.0;  // root at 1, or even p = 1 is too transparent: clamp to 1
  const double start = f0 / -dF_log(alphas, 0.0);
  if (start > 0 && start < 1) {
    const double f = F(start);
    if (f == 0) return start;
    if (f < 0) hi = start, fhi = f;
  }
  std::uintmax_t iterations = 200;
  const auto bracket = boost::math::tools::toms748_solve(F, 0.0, hi, f0, fhi,
                                                         boost::math::tools::eps_tolerance<double>(), iterations);
  const double lo = bracket.first, up = bracket.second;
  // The bracket is a few ulps wide: take the best of its ends, its middle and one Newton step
  // from the middle (kept inside the bracket).
  double best = lo, best_f = std::fabs(F(lo));
  const auto consider = [&](double p) {
    if (!(p >= lo && p <= up)) return;
    const double f = std::fabs(F(p));
    if (f < best_f) best = p, best_f = f;
  };
  consider(up);
  const double mid = lo + (up - lo) / 2;
  const double fmid = F(mid);
  if (std::fabs(fmid) < best_f) best = mid, best_f = std::fabs(fmid);
  const double d = dF_log(alphas, mid);
  if (std::isfinite(d) && d < 0) consider(mid - fmid / d);
  return std::clamp(best, 0.0, 1.0);
}

// The fit's matrix of eq. 14 for p0, p1, p2 = 0, 1/2, 1, inverted once.
const Eigen::Matrix3d& fit_inverse() {
  static const Eigen::Matrix3d inverse = [] {
    const double p[3] = {0.0, 0.5, 1.0};
    Eigen::Matrix3d m;
    for (int i = 0; i < 3; ++i) m.row(i) << p[i] * p[i], p[i], 1.0;
    return Eigen::Matrix3d(m.inverse());
  }();
  return inverse;
}

double quadratic_p(std::span<const double> alphas, const Target& t) {
  if (auto p = decided_p(alphas, t)) return *p;
  const double target = t.transparency;  // 1 - alpha_unit
  const auto product = [&](double p) {
    double prod = 1;
    for (double a : alphas) prod *= 1 - p * clamp01(a);
    return prod;
  };
  // F(p) = prod (1 - p alpha_k) - (1 - alpha_unit): eq. 11 times (-1)^N, evaluated as a product.
  const double g0 = t.unit;  // F(0)
  const double gh = product(0.5) - target;
  const double g1 = product(1.0) - target;
  if (g1 >= 0) return 1.0;  // as exact_p
  const Eigen::Vector3d abc = fit_inverse() * Eigen::Vector3d(g0, gh, g1);
  const double A = abc[0], B = abc[1], C = abc[2];
  // Cancellation-free roots q / A and C / q; a discriminant that rounds negative is a double root.
  const double disc = std::max(0.0, B * B - 4 * A * C);
  const double q = -0.5 * (B + std::copysign(std::sqrt(disc), B));
  double best = g0 / (g0 - g1);  // fallback: the secant of the bracket, inside (0, 1)
  double best_distance = std::numeric_limits<double>::infinity();
  bool best_descending = false;
  const auto consider = [&](double r) {
    if (!std::isfinite(r)) return;
    const double distance = std::max({0.0, -r, r - 1});
    const bool descending = 2 * A * r + B <= 0;  // F decreases through its root
    if (distance < best_distance || (distance == best_distance && descending && !best_descending))
      best = r, best_distance = distance, best_descending = descending;
  };
  if (q != 0) consider(C / q);
  if (A != 0) consider(q / A);
  return std::clamp(best, 0.0, 1.0);
}

Target unit_target(double alpha_unit) {
  const double a = clamp01(alpha_unit);
  return {std::log1p(-a), 1 - a, a};
}

}  // namespace

constexpr NameTable<Correction, 5> kCorrectionNames{{
    {Correction::none, "none"},
    {Correction::lacroute, "lacroute"},
    {Correction::schulze, "schulze"},
    {Correction::lee_newman, "lee_newman"},
    {Correction::lee_newman_quadratic, "lee_newman_quadratic"},
}};
static_assert(names_complete(kCorrectionNames));

std::optional<Correction> parse_correction(std::string_view name) { return parse_name(kCorrectionNames, name); }
std::string correction_list() { return name_list(kCorrectionNames); }

std::string_view correction_name(Correction c) { return name_of(kCorrectionNames, c); }

double lacroute(double alpha, int N) {
  check_factor(N);
  const double a = clamp01(alpha);
  if (N == 1 || a == 0 || a == 1) return a;
  return clamp01(-std::expm1(std::log1p(-a) / N));
}

double schulze_color_scale(double alpha, int N) {
  check_factor(N);
  const double a = clamp01(alpha);
  if (N == 1 || a == 1) return 1.0;
  const double n = N;
  // alpha'/alpha = (1/N) (1 + (N-1)/(2N) alpha + O(alpha^2)); below 1e-9 the series is exact to
  // rounding and avoids x / N becoming subnormal.
  if (a < 1e-9) return (1 + (n - 1) / (2 * n) * a) / n;
  const double x = std::log1p(-a);
  return std::expm1(x / n) / std::expm1(x);
}

double lee_newman_p(std::span<const double> alphas, double alpha_unit) {
  return exact_p(alphas, unit_target(alpha_unit));
}

double lee_newman_quadratic_p(std::span<const double> alphas, double alpha_unit) {
  return quadratic_p(alphas, unit_target(alpha_unit));
}

void correct_group(Correction c, std::span<double> alphas, std::span<double> colors, int N,
                   std::optional<double> alpha_unit) {
  check_factor(N);
  if (!colors.empty() && colors.size() != alphas.size())
    throw std::invalid_argument("correct_group: colors must be empty or as many as alphas");
  switch (c) {
    case Correction::none:
      return;
    case Correction::lacroute:
      for (double& a : alphas) a = lacroute(a, N);
      return;
    case Correction::schulze:
      for (std::size_t k = 0; k < alphas.size(); ++k) {
        if (!colors.empty()) colors[k] *= schulze_color_scale(alphas[k], N);
        alphas[k] = lacroute(alphas[k], N);
      }
      return;
    case Correction::lee_newman:
    case Correction::lee_newman_quadratic: {
      if (alphas.empty()) return;
      if (alphas.size() > static_cast<std::size_t>(N))
        throw std::invalid_argument("correct_group: a Lee & Newman group has at most N samples");
      for (double& a : alphas) a = clamp01(a);
      const std::size_t m = alphas.size();
      Target t = unit_target(alpha_unit ? *alpha_unit : alphas[0]);
      if (m < static_cast<std::size_t>(N)) {  // partial group: (1 - alpha_1)^(m/N)
        t.log_target *= static_cast<double>(m) / N;
        t.transparency = std::exp(t.log_target);
        t.unit = -std::expm1(t.log_target);
      }
      const std::span<const double> group(alphas.data(), m);
      const double p = c == Correction::lee_newman ? exact_p(group, t) : quadratic_p(group, t);
      for (double& a : alphas) a = clamp01(p * a);
      return;
    }
  }
}

}  // namespace vrv
