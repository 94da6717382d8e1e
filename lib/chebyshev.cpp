#include "lib/chebyshev.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <numbers>
#include <stdexcept>

namespace vrv {

ChebyshevRule::ChebyshevRule(int n)
    : n_(n),
      nodes_(n),
      to_coefficients_(static_cast<std::size_t>(n) * n),
      cumulative_(static_cast<std::size_t>(n) * n),
      weights_(n),
      cumulative_row_abs_(n) {
  if (n == 1) {
    nodes_[0] = 0;
    entry(to_coefficients_, 0, 0) = 1;
    entry(cumulative_, 0, 0) = 1;  // int_{-1}^{0} of a constant, as the midpoint rule sees it
    weights_[0] = 2;
    cumulative_row_abs_[0] = 1;
    return;
  }
  const double pi = std::numbers::pi;
  const int m = n - 1;
  for (int j = 0; j < n; ++j) nodes_[j] = std::cos(pi * j / m);
  // Symmetric nodes exactly: cos() rounding would make x_j and -x_{m-j} differ in the last bit.
  for (int j = 0; j < n / 2; ++j) nodes_[m - j] = -nodes_[j];
  if (n % 2 == 1) nodes_[m / 2] = 0;
  // Discrete cosine transform of type I: c_k = (2/m) sum'' f_j cos(pi j k / m).
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j) {
      double w = 2.0 / m * std::cos(pi * ((static_cast<long>(j) * k) % (2 * m)) / m);
      if (j == 0 || j == m) w *= 0.5;
      if (k == 0 || k == m) w *= 0.5;
      entry(to_coefficients_, k, j) = w;
    }
  // Column j: the cumulative integral of the interpolant of the j-th unit vector.
  std::vector<double> c(n), anti(n + 1);
  for (int j = 0; j < n; ++j) {
    for (int k = 0; k < n; ++k) c[k] = entry(to_coefficients_, k, j);
    chebyshev_antiderivative(c, anti);
    for (int i = 0; i < n; ++i) entry(cumulative_, i, j) = chebyshev_evaluate(anti, nodes_[i]);
    weights_[j] = chebyshev_integral(c);
  }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) cumulative_row_abs_[i] += std::abs(entry(cumulative_, i, j));
}

const ChebyshevRule& ChebyshevRule::get(int n) {
  constexpr int max_n = 129;
  if (n < 1 || n > max_n) throw std::out_of_range("ChebyshevRule: n must be in [1, 129]");
  static std::array<std::unique_ptr<ChebyshevRule>, max_n + 1> cache;
  static std::once_flag flags[max_n + 1];
  std::call_once(flags[n], [n] { cache[n].reset(new ChebyshevRule(n)); });
  return *cache[n];
}

namespace {

// out = M x for column-major n x n M, column after column (each row's sum in column order).
// With n known at compile time the loops unroll and the rows vectorise; the order of every
// row's sum is the same, so the values are bitwise those of the runtime-n loop.
template <std::size_t N>
void apply_fixed(const double* m, const double* x, double* out) {
  double acc[N] = {};
  for (std::size_t j = 0; j < N; ++j) {
    const double xj = x[j];
    const double* column = m + j * N;
    for (std::size_t k = 0; k < N; ++k) acc[k] += column[k] * xj;
  }
  std::copy_n(acc, N, out);
}

void apply_any(std::size_t n, const double* m, const double* x, double* out) {
  std::fill_n(out, n, 0.0);
  for (std::size_t j = 0; j < n; ++j) {
    const double xj = x[j];
    const double* column = m + j * n;
    for (std::size_t k = 0; k < n; ++k) out[k] += column[k] * xj;
  }
}

}  // namespace

void ChebyshevRule::apply(const std::vector<double>& m, std::span<const double> x, std::span<double> out) const {
  // The sizes of the hot paths: a grid cell's cubic (4) and the ladder of its pieces (9, 17, 33).
  switch (n_) {
    case 4: return apply_fixed<4>(m.data(), x.data(), out.data());
    case 9: return apply_fixed<9>(m.data(), x.data(), out.data());
    case 17: return apply_fixed<17>(m.data(), x.data(), out.data());
    case 33: return apply_fixed<33>(m.data(), x.data(), out.data());
    default: return apply_any(static_cast<std::size_t>(n_), m.data(), x.data(), out.data());
  }
}

void ChebyshevRule::coefficients(std::span<const double> values, std::span<double> c) const {
  apply(to_coefficients_, values, c);
}

void ChebyshevRule::cumulative_integral(std::span<const double> values, std::span<double> out) const {
  apply(cumulative_, values, out);
}

double chebyshev_evaluate(std::span<const double> c, double x) {
  double b1 = 0, b2 = 0;
  const double two_x = 2 * x;
  for (std::size_t k = c.size(); k-- > 1;) {
    const double b0 = c[k] + two_x * b1 - b2;
    b2 = b1;
    b1 = b0;
  }
  return c.empty() ? 0.0 : c[0] + x * b1 - b2;
}

void chebyshev_evaluate_many(std::span<const double> c, std::span<const double> x, std::span<double> out) {
  constexpr std::size_t block = 8;
  for (std::size_t i0 = 0; i0 < x.size(); i0 += block) {
    const std::size_t m = std::min(block, x.size() - i0);
    double xs[block] = {}, two_x[block], b1[block] = {}, b2[block] = {};
    for (std::size_t i = 0; i < m; ++i) xs[i] = x[i0 + i];
    for (std::size_t i = 0; i < block; ++i) two_x[i] = 2 * xs[i];
    for (std::size_t k = c.size(); k-- > 1;)
      for (std::size_t i = 0; i < block; ++i) {
        const double b0 = c[k] + two_x[i] * b1[i] - b2[i];
        b2[i] = b1[i];
        b1[i] = b0;
      }
    for (std::size_t i = 0; i < m; ++i) out[i0 + i] = c.empty() ? 0.0 : c[0] + xs[i] * b1[i] - b2[i];
  }
}

void chebyshev_antiderivative(std::span<const double> c, std::span<double> out) {
  const std::size_t n = c.size();
  auto at = [&](std::size_t k) { return k < n ? c[k] : 0.0; };
  std::fill(out.begin(), out.end(), 0.0);
  // int T_k = T_{k+1}/(2(k+1)) - T_{k-1}/(2(k-1)), int T_0 = T_1, int T_1 = T_2 / 4 (+ const).
  for (std::size_t k = 1; k <= n; ++k) {
    const double lower = k == 1 ? 2 * at(0) : at(k - 1);
    out[k] = (lower - at(k + 1)) / (2.0 * k);
  }
  double at_minus_one = 0;  // F(-1) without the constant term
  for (std::size_t k = 1; k <= n; ++k) at_minus_one += (k % 2 ? -out[k] : out[k]);
  out[0] = -at_minus_one;
}

void chebyshev_derivative(std::span<const double> c, std::span<double> out) {
  const std::size_t n = c.size();
  std::fill(out.begin(), out.end(), 0.0);
  // d_k = d_{k+2} + 2 (k + 1) c_{k+1}, then d_0 halved.
  for (std::size_t k = n - 1; k-- > 0;) out[k] = (k + 2 < n ? out[k + 2] : 0.0) + 2.0 * (k + 1) * c[k + 1];
  if (n > 0) out[0] *= 0.5;
}

double chebyshev_integral(std::span<const double> c) {
  double sum = 0;
  for (std::size_t k = 0; k < c.size(); k += 2) sum += 2.0 * c[k] / (1.0 - static_cast<double>(k * k));
  return sum;
}

namespace {

// 2/pi ln(n - 1) + 1, the Lebesgue constant of n Chebyshev points: a table up to 129 points
// (the same values, without a logarithm on every accuracy check of the hot path).
double lebesgue_constant(int n) {
  const auto formula = [](int m) { return m > 2 ? 2 / std::numbers::pi * std::log(m - 1.0) + 1 : 1.0; };
  static const auto table = [&] {
    std::array<double, 130> t{};
    for (int m = 0; m < 130; ++m) t[m] = formula(m);
    return t;
  }();
  return n >= 0 && n < 130 ? table[n] : formula(n);
}

}  // namespace

ChebyshevAccuracy chebyshev_accuracy(std::span<const double> c, double noise) {
  const int n = static_cast<int>(c.size());
  const double eps = std::numeric_limits<double>::epsilon();
  double scale = 0, sum = 0;
  for (double x : c) scale = std::max(scale, std::abs(x)), sum += std::abs(x);
  // Rounding in the sampled values (noise) reaches the interpolant amplified at most by the
  // Lebesgue constant of Chebyshev points, 2/pi ln(n - 1) + 1; Clenshaw's recurrence adds
  // about eps sqrt(n) sum |c_k| when the interpolant is evaluated.
  const double value_noise = std::max(noise, 2 * eps * scale);
  const double lebesgue = lebesgue_constant(n);
  const double rounding_error =
      lebesgue * value_noise + 2 * eps * std::sqrt(static_cast<double>(n)) * sum;
  // Coefficients of noise of that size sit below this level.
  const double floor = std::max(4 * eps * scale * std::sqrt(static_cast<double>(n)), noise);
  const double noise_error = lebesgue * value_noise;
  if (n < 8) {
    // Too short to judge decay: only exact (polynomial) data, used for known-degree pieces.
    return {rounding_error, true, true, noise_error};
  }
  // Pairs, so that an odd or even function's zero coefficients do not fake convergence.
  const double tail = std::max(std::abs(c[n - 1]), std::abs(c[n - 2]));
  const double before = std::max(std::abs(c[n - 5]), std::abs(c[n - 6])) +
                        std::numeric_limits<double>::min();
  if (tail <= floor) return {2 * tail + rounding_error, true, true, noise_error};
  // Geometric decay rate per degree from the last few coefficients; the neglected tail
  // sum_{k >= n} |a_k| plus aliasing is about 2 tail r / (1 - r).
  const double r = std::pow(tail / before, 0.25);
  if (!(r < 0.8)) return {2 * tail / 0.2, false, false, 0};
  return {2 * tail * r / (1 - r) + rounding_error, true, false, noise_error};
}

}  // namespace vrv
