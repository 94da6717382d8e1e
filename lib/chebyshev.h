#pragma once
// Chebyshev-Lobatto interpolation on [-1, 1]: the spectral tool behind the reference
// integrator's panels.  Values at x_j = cos(pi j / (n - 1)) become coefficients of
// p(x) = sum_k c_k T_k(x); p can then be evaluated, integrated and its accuracy judged from
// how fast the coefficients decay (Trefethen, "Approximation Theory and Practice").
#include <span>
#include <vector>


namespace vrv {

class ChebyshevRule {
 public:
  // The rule with n points (cached; n from 1 to 129).  n = 1 is the midpoint.
  static const ChebyshevRule& get(int n);

  int size() const { return n_; }
  double node(int j) const { return nodes_[j]; }  // from +1 down to -1
  // Coefficients c_0..c_{n-1} of the interpolant through values[j] at node(j).
  void coefficients(std::span<const double> values, std::span<double> c) const;
  // int_{-1}^{x_j} p(x) dx at every node, from the values (one matrix product: the spectral
  // integration matrix, built once per rule).
  void cumulative_integral(std::span<const double> values, std::span<double> out) const;
  // The Clenshaw-Curtis weight of node j (all positive, summing to 2): int_{-1}^{1} p =
  // sum_j weight(j) values[j], so noise d_j in the values moves the integral by sum_j w_j d_j.
  double weight(int j) const { return weights_[j]; }
  // sum_k |Q_jk|: bounds the rounding of the cumulative integral at node j by the values' size.
  double cumulative_row_abs(int j) const { return cumulative_row_abs_[j]; }

 private:
  explicit ChebyshevRule(int n);
  int n_;
  std::vector<double> nodes_;
  // Column-major n x n; applied by a plain loop, column after column: for the small n the hot
  // paths use (9 on a grid cell), a general dynamic-size product spent more in dispatch than in
  // arithmetic (issue 23's profile).  The order of the sums is the one Eigen's column-major
  // product uses without FMA, so the values are the same bit for bit.
  std::vector<double> to_coefficients_;  // c = M * values
  std::vector<double> cumulative_;       // cumulative integral at the nodes = Q * values
  std::vector<double> weights_;
  std::vector<double> cumulative_row_abs_;
  double& entry(std::vector<double>& m, int row, int col) { return m[static_cast<std::size_t>(col) * n_ + row]; }
  void apply(const std::vector<double>& m, std::span<const double> x, std::span<double> out) const;
};

// p(x) by Clenshaw's recurrence.
double chebyshev_evaluate(std::span<const double> c, double x);
// p at every x[i] into out[i]: several points per pass over the coefficients, each with exactly
// the operations of chebyshev_evaluate (bitwise the same values), but sharing the loads and
// overlapping the independent recurrences.
void chebyshev_evaluate_many(std::span<const double> c, std::span<const double> x, std::span<double> out);
// Coefficients of the antiderivative F with F(-1) = 0 (one more coefficient than c).
void chebyshev_antiderivative(std::span<const double> c, std::span<double> out);
// Coefficients of the derivative p' (same length as c; the last is zero).
void chebyshev_derivative(std::span<const double> c, std::span<double> out);
// Integral of p over [-1, 1].
double chebyshev_integral(std::span<const double> c);

// A posteriori bound on max |f - p| from the decay of the last coefficients.
struct ChebyshevAccuracy {
  double error = 0;       // estimated max |f - p| on the interval
  bool resolved = false;  // the coefficients decay (or sit at round-off level)
  bool at_rounding = false;  // the tail is rounding noise: splitting the interval cannot help
  // The part of `error` that is the values' noise amplified by the Lebesgue constant: a max-norm
  // bound, which an integral can replace by the weighted sum of the nodes' own noise.
  double noise_error = 0;
};
// `noise` is the absolute rounding level of the sampled values when it exceeds what their
// size implies (values computed by subtracting larger numbers).
ChebyshevAccuracy chebyshev_accuracy(std::span<const double> c, double noise = 0);

}  // namespace vrv
