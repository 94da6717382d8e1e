// zeta and Psi of a unit segment: linear opacity (the thesis' exact values), linear extinction
// (vrv's exact_linear) and the average-opacity approximation (vrv's moreland rule).
#include <algorithm>
#include <cmath>
#include <limits>

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/quadrature/tanh_sinh.hpp>

#include "analytic/piece_integrals.h"
#include "lib/segment_rule.h"
#include "studies/segment-rules/segment_rules.h"

namespace vrv {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Transparency of a unit length left at s: u(s) = 1 - alpha(s), linear in s.
struct LinearTransparency {
  double u_f, u_b;
  double at(double s) const { return u_f + (u_b - u_f) * s; }
};

// exp(-Phi(s)) with Phi(s) = -int_0^s ln u = -s mean_log(u_f, u(s)).
double transmittance(const LinearTransparency& u, double s) {
  if (s <= 0) return 1;
  return std::exp(s * mean_log(u.u_f, u.at(s)));
}

// Adaptive Gauss-Kronrod; its error estimate (Kronrod against Gauss) is far above the error.
template <class F>
double gauss_kronrod(F f, double a, double b) {
  return boost::math::quadrature::gauss_kronrod<double, 31>::integrate(f, a, b, 8, 1e-13);
}

}  // namespace

double mean_log(double a, double b) {
  const double hi = std::max(a, b), lo = std::min(a, b);
  if (hi == 0) return -kInf;
  if (lo == 0) return std::log(hi) - 1;
  // (hi ln hi - lo ln lo)/(hi - lo) - 1 = ln hi - 1 - r ln r/(1 - r), r = lo/hi, ln r = log1p(-e).
  const double e = (hi - lo) / hi, r = lo / hi;
  if (e == 0) return std::log(hi);
  return std::log(hi) - 1 - r * std::log1p(-e) / e;
}

ZetaPsi linear_alpha_segment(double alpha_f, double alpha_b) {
  const LinearTransparency u{1 - alpha_f, 1 - alpha_b};
  // The transmittance's derivatives blow up (logarithmically) where u reaches 0 at an end:
  // tanh-sinh does not mind endpoint singularities.
  thread_local boost::math::quadrature::tanh_sinh<double> tanh_sinh;  // integrate() is not const
  const double psi =
      tanh_sinh.integrate([&](double s) { return transmittance(u, s); }, 0.0, 1.0, 1e-15);
  return {std::exp(mean_log(u.u_f, u.u_b)), psi};
}

ZetaPsi linear_tau_segment(double alpha_f, double alpha_b) {
  const double tau_f = -std::log1p(-alpha_f), tau_b = -std::log1p(-alpha_b);
  const PieceIntegral p = linear_piece(1.0, 1.0, 1.0, tau_f, tau_b);  // g = 1: E = Psi
  return {std::exp(-p.optical_depth), p.emission};
}

ZetaPsi average_opacity_segment(double alpha_f, double alpha_b) {
  // I = c_f (1 - Psi) + c_b (Psi - zeta): colours (1, 0) give 1 - Psi.
  const Composite<double> c = moreland_segment<double>(1.0, 0.0, alpha_f, alpha_b);
  return {c.transparency, 1 - c.emission};
}

ZetaPsi linear_alpha_by_quadrature(double alpha_f, double alpha_b) {
  const LinearTransparency u{1 - alpha_f, 1 - alpha_b};
  auto tau = [&](double s) { return -std::log(u.at(s)); };
  auto phi = [&](double s) { return s > 0 ? gauss_kronrod(tau, 0.0, s) : 0.0; };
  return {std::exp(-phi(1.0)), gauss_kronrod([&](double s) { return std::exp(-phi(s)); }, 0.0, 1.0)};
}

ZetaPsi linear_tau_by_quadrature(double alpha_f, double alpha_b) {
  const double tau_f = -std::log1p(-alpha_f), tau_b = -std::log1p(-alpha_b);
  auto tau = [&](double s) { return tau_f + (tau_b - tau_f) * s; };
  auto phi = [&](double s) { return s > 0 ? gauss_kronrod(tau, 0.0, s) : 0.0; };
  return {std::exp(-phi(1.0)), gauss_kronrod([&](double s) { return std::exp(-phi(s)); }, 0.0, 1.0)};
}

std::vector<double> opacity_grid(long n, double top) {
  std::vector<double> alphas;
  for (long i = 0; i < n; ++i)
    alphas.push_back(i + 1 == n ? top : static_cast<double>(i) / static_cast<double>(n - 1));
  return alphas;
}

}  // namespace vrv
