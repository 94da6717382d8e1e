// The closed forms of analytic/piece_integrals against 50-digit adaptive quadrature.
#include "analytic/piece_integrals.h"

#include <cmath>
#include <random>

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/multiprecision/cpp_bin_float.hpp>
#include <gtest/gtest.h>

namespace vrv {
namespace {

using Real = boost::multiprecision::cpp_bin_float_50;

// E = int_0^L g(s) exp(-int_0^s tau) ds with g, tau linear, in 50 digits.
double emission_50_digits(double L, double g0, double g1, double tau0, double tau1) {
  const Real len = L, a = g0, b = (Real(g1) - g0) / len, c = tau0, d = (Real(tau1) - tau0) / len;
  auto integrand = [&](const Real& s) { return (a + b * s) * exp(-(c * s + d * s * s / 2)); };
  // Piecewise in optical depth so the adaptive rule sees a gently varying integrand.
  Real total = 0, s = 0;
  const int pieces = 1 + static_cast<int>(std::min(200.0, 0.5 * L * (tau0 + tau1)));
  for (int k = 1; k <= pieces; ++k) {
    const Real e = len * k / pieces;
    total += boost::math::quadrature::gauss_kronrod<Real, 31>::integrate(integrand, s, e, 20,
                                                                         Real(1e-40));
    s = e;
  }
  return static_cast<double>(total);
}

struct Case {
  double L, g0, g1, tau0, tau1;
};

void expect_close(const Case& k, double tolerance) {
  const double exact = emission_50_digits(k.L, k.g0, k.g1, k.tau0, k.tau1);
  const PieceIntegral p = linear_piece(k.L, k.g0, k.g1, k.tau0, k.tau1);
  ASSERT_TRUE(std::isfinite(p.emission));
  EXPECT_LE(std::abs(p.emission - exact), tolerance * std::abs(exact) + 1e-300)
      << "L=" << k.L << " g=" << k.g0 << ".." << k.g1 << " tau=" << k.tau0 << ".." << k.tau1
      << " got " << p.emission << " exact " << exact;
  EXPECT_DOUBLE_EQ(p.optical_depth, 0.5 * k.L * (k.tau0 + k.tau1));
}

// Expected-error table over the regimes the implementation switches between.
TEST(PieceIntegrals, LinearPieceMatches50DigitQuadrature) {
  const Case cases[] = {
      {1, 0.3, 0.9, 0.1, 0.4},          // thin: Gauss-Legendre branch
      {1, 1, 2, 1e-12, 3e-12},          // extinction ~1e-12: no 0/0
      {0.5, 0, 1, 0, 0},                // no extinction at all
      {2, 0.2, 1.0, 0.5, 3.0},          // rising extinction: erfcx form
      {1, 1, 0, 0, 10},                 // from zero extinction
      {1, 1, 1, 0, 2000},               // depth 1000
      {2, 0.2, 1.0, 3.0, 0.5},          // falling extinction: Dawson form
      {1, 0.5, 0.1, 10, 0},             // falling to zero
      {3, 1, 1, 5, 4.9999},             // nearly constant, falling
      {1, 0, 1, 5, 5 + 1e-12},          // extinction slope 1e-12: conditioning fallback
      {1, 0, 1, 5, 5},                  // constant extinction
      {1, 1, 0, 5, 5 - 1e-9},
      {1, 2, 2, 3, 4},                  // constant emission
      {1, 0, 1, 3000, 3000.001},        // huge depth with an emission slope
      {1e-9, 1, 2, 1, 2},               // corner chord
      {10, 0.7, 0.7, 0.9, 1.1},
  };
  for (const Case& k : cases) expect_close(k, 2e-14);
}

TEST(PieceIntegrals, RandomRegimesStayWithinAFewUlps) {
  std::mt19937_64 rng(20261122);
  std::uniform_real_distribution<double> unit(0, 1);
  auto log_uniform = [&](double lo, double hi) { return std::pow(10.0, lo + (hi - lo) * unit(rng)); };
  for (int i = 0; i < 150; ++i) {
    const Case k{log_uniform(-3, 1), unit(rng), unit(rng), log_uniform(-6, 3) * (unit(rng) < 0.1 ? 0 : 1),
                 log_uniform(-6, 3)};
    expect_close(k, 4e-14);
  }
}

TEST(PieceIntegrals, ConstantPieceIsStableAtBothEnds) {
  EXPECT_DOUBLE_EQ(constant_piece(2, 3, 0).emission, 6);            // no extinction: g L
  EXPECT_NEAR(constant_piece(1, 1, 1e-300).emission, 1, 1e-16);   // no 0/0
  EXPECT_NEAR(constant_piece(1, 2, 1e4).emission, 2e-4, 1e-19);   // opaque: g / tau
  EXPECT_NEAR(constant_piece(1, 1, 1).emission, 1 - std::exp(-1.0), 1e-16);
  EXPECT_DOUBLE_EQ(escape_fraction(0), 1);
  EXPECT_NEAR(escape_fraction(1e-10), 1 - 5e-11, 1e-20);
}

}  // namespace
}  // namespace vrv
