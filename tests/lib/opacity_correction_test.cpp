#include "lib/opacity_correction.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <random>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace vrv {
namespace {

constexpr Correction kAll[] = {Correction::none, Correction::lacroute, Correction::schulze,
                               Correction::lee_newman, Correction::lee_newman_quadratic};

// Front-to-back compositing of one group (eqs. 1 and 3: I_i = C_i alpha_i).
struct CompositedRay {
  double opacity = 0;
  double intensity = 0;
};
CompositedRay composite(const std::vector<double>& alphas, const std::vector<double>& colors) {
  long double transparency = 1, intensity = 0;
  for (std::size_t k = 0; k < alphas.size(); ++k) {
    intensity += transparency * colors[k] * alphas[k];
    transparency *= 1 - static_cast<long double>(alphas[k]);
  }
  return {static_cast<double>(1 - transparency), static_cast<double>(intensity)};
}

// sum log1p(-p alpha_k) - log1p(-alpha_unit) in long double: the defining equation's residual in
// log space (= the relative error of the group's transparency).
long double residual(const std::vector<double>& alphas, double alpha_unit, double p) {
  long double s = -std::log1p(-static_cast<long double>(alpha_unit));
  for (double a : alphas) s += std::log1p(-static_cast<long double>(p) * a);
  return s;
}

// |dF/dp| at p: how much one ulp of p moves the residual (the equation's own conditioning).
double slope(const std::vector<double>& alphas, double p) {
  double d = 0;
  for (double a : alphas) d += a / (1 - p * a);
  return d;
}

double corrected_p(Correction c, const std::vector<double>& alphas) {
  return c == Correction::lee_newman ? lee_newman_p(alphas, alphas[0]) : lee_newman_quadratic_p(alphas, alphas[0]);
}

TEST(OpacityCorrection, ParseAndNameRoundTrip) {
  for (Correction c : kAll) EXPECT_EQ(parse_correction(correction_name(c)), c);
  EXPECT_EQ(correction_name(Correction::lee_newman_quadratic), "lee_newman_quadratic");
  EXPECT_FALSE(parse_correction("Lacroute").has_value());
  EXPECT_FALSE(parse_correction("").has_value());
  EXPECT_FALSE(parse_correction("lee-newman").has_value());
}

TEST(OpacityCorrection, InvalidArgumentsThrow) {
  std::vector<double> a{0.5, 0.5, 0.5}, c{1, 1};
  EXPECT_THROW(lacroute(0.5, 0), std::invalid_argument);
  EXPECT_THROW(schulze_color_scale(0.5, -1), std::invalid_argument);
  EXPECT_THROW(correct_group(Correction::lacroute, a, {}, 0), std::invalid_argument);
  EXPECT_THROW(correct_group(Correction::schulze, a, c, 3), std::invalid_argument);
  EXPECT_THROW(correct_group(Correction::lee_newman, a, {}, 2), std::invalid_argument);  // 3 > N
}

TEST(OpacityCorrection, LacrouteIsExactForAHomogeneousMedium) {
  const std::vector<double> alphas{1e-300, 1e-12, 1e-6, 1e-3, 0.01, 0.1, 0.25, 67.0 / 255, 0.5,
                                   0.75, 0.9, 0.99, 0.999999, 1 - 1e-12, 1 - 0x1p-53};
  const std::vector<int> Ns{1, 2, 3, 4, 5, 7, 10, 16, 64, 100, 255, 256, 999, 1000, 1023, 1024};
  double worst = 0;
  for (double a : alphas)
    for (int N : Ns) {
      const double c = lacroute(a, N);
      ASSERT_GE(c, 0);
      ASSERT_LE(c, a);
      // 1 - (1 - alpha')^N, in long double log space.
      const long double total = -std::expm1(N * std::log1p(-static_cast<long double>(c)));
      const double err = std::fabs(static_cast<double>(total) - a);
      worst = std::max(worst, err);
      EXPECT_LE(err, 1e-15) << "alpha " << a << " N " << N;
      EXPECT_LE(err, 4e-16 * a) << "relative, alpha " << a << " N " << N;
    }
  std::cout << "lacroute homogeneous: worst |composited - alpha| = " << worst << "\n";
  EXPECT_EQ(lacroute(0, 7), 0);
  EXPECT_EQ(lacroute(1, 7), 1);
  EXPECT_EQ(lacroute(0.3, 1), 0.3);
}

TEST(OpacityCorrection, SchulzeColourScaleIsAlphaRatioWithLimits) {
  for (int N : {2, 5, 1024}) {
    EXPECT_DOUBLE_EQ(schulze_color_scale(0, N), 1.0 / N);
    EXPECT_EQ(schulze_color_scale(1, N), 1.0);
    for (double a : {1e-3, 0.1, 0.5, 0.9, 0.999})
      EXPECT_NEAR(schulze_color_scale(a, N), lacroute(a, N) / a, 1e-14 * (lacroute(a, N) / a));
    // Continuous through 0 and monotone increasing in alpha (from 1/N to 1).
    double previous = schulze_color_scale(0, N);
    for (double a : {1e-300, 1e-20, 1e-10, 1e-9, 2e-9, 1e-8, 1e-4, 0.01, 0.3, 0.7, 1 - 1e-9, 1.0}) {
      const double s = schulze_color_scale(a, N);
      EXPECT_GE(s, previous) << a;
      EXPECT_LE(s, 1.0);
      previous = s;
    }
    // Both branches (series below 1e-9, closed form above) against a long double reference.
    for (double a : {1e-300, 1e-15, 0.999e-9, 1.001e-9, 1e-7, 0.2, 1 - 1e-12}) {
      const long double x = std::log1p(-static_cast<long double>(a));
      const double reference = static_cast<double>(std::expm1(x / N) / std::expm1(x));
      EXPECT_NEAR(schulze_color_scale(a, N), reference, 4e-16 * reference) << "alpha " << a << " N " << N;
    }
  }
  EXPECT_EQ(schulze_color_scale(0.4, 1), 1.0);
}

TEST(OpacityCorrection, LeeNewmanSolvesItsEquationToFullPrecision) {
  std::mt19937_64 rng(20070129);
  std::uniform_real_distribution<double> uniform(0, 1);
  std::uniform_int_distribution<int> factor(2, 1024), byte(0, 255), kind(0, 4);
  std::vector<int> Ns{2, 3, 4, 5, 8, 16, 100, 1023, 1024};
  for (int i = 0; i < 2000; ++i) Ns.push_back(factor(rng));
  long double worst = 0;
  int worst_N = 0, checked = 0, max_ulps_off = 0;
  for (int N : Ns) {
    const int k = kind(rng);
    std::vector<double> a(N);
    for (double& x : a) {
      switch (k) {
        case 0: x = uniform(rng); break;                          // i.i.d. uniform
        case 1: x = byte(rng) / 255.0; break;                     // 8-bit samples, zeros and ones
        case 2: x = std::pow(uniform(rng), 8); break;             // mostly faint
        case 3: x = 1 - std::pow(uniform(rng), 8); break;         // mostly dense
        default: x = uniform(rng) < 0.9 ? 0.0 : uniform(rng);     // sparse
      }
    }
    if (uniform(rng) < 0.5) a[0] = 0.05 + 0.9 * uniform(rng);  // keep a non-trivial target often
    const double p = lee_newman_p(a, a[0]);
    ASSERT_TRUE(std::isfinite(p));
    ASSERT_GE(p, 0);
    ASSERT_LE(p, 1);
    if (a[0] == 0 || a[0] == 1) continue;  // p = 0 or p = 1 by convention, checked elsewhere
    ++checked;
    const long double r = residual(a, a[0], p);
    const double log_target = std::fabs(std::log1p(-a[0]));
    // 1e-14 on the log transparency, plus what one ulp of p moves it (a group with some
    // 1 - p alpha_k tiny is ill-conditioned however p is computed).
    const double ulp = std::nextafter(p, 2.0) - p;
    const double tolerance = 1e-14 * std::max(1.0, log_target) + 2 * slope(a, p) * ulp;
    EXPECT_LE(std::fabs(static_cast<double>(r)), tolerance) << "N " << N << " kind " << k << " p " << p;
    if (std::fabs(r) > worst) worst = std::fabs(r), worst_N = N;
    // Full double precision: the exact root lies within a few ulps of p (the long double residual
    // changes sign there).
    double lo = p, hi = p;
    int ulps = 0;
    while (residual(a, a[0], lo) < 0 && ulps < 64) lo = std::nextafter(lo, -1.0), ++ulps;
    int ulps_hi = 0;
    while (residual(a, a[0], hi) > 0 && ulps_hi < 64) hi = std::nextafter(hi, 2.0), ++ulps_hi;
    max_ulps_off = std::max({max_ulps_off, ulps, ulps_hi});
  }
  std::cout << "lee_newman: " << checked << " random groups (N = 2..1024), worst |log residual| = "
            << static_cast<double>(worst) << " (N = " << worst_N << "), p at most " << max_ulps_off
            << " ulp from the root\n";
  EXPECT_LE(max_ulps_off, 2);
}

TEST(OpacityCorrection, LeeNewmanOnAHomogeneousGroupIsLacroute) {
  // Eq. 9 with alpha_o1 = alpha_o2 = alpha gives (1 - p alpha)^2 = 1 - alpha, i.e. p alpha =
  // 1 - sqrt(1 - alpha) = eq. 5: on a homogeneous group the new correction is Lacroute's.
  for (int N : {2, 3, 5, 10, 64, 255, 1024})
    for (double a : {1e-9, 1e-3, 0.1, 67.0 / 255, 0.5, 0.9, 0.999999}) {
      std::vector<double> group(N, a), colors(N, 1.0);
      const double p = lee_newman_p(group, a);
      EXPECT_NEAR(p * a, lacroute(a, N), 4e-16 * lacroute(a, N)) << "N " << N << " alpha " << a;
      correct_group(Correction::lee_newman, group, colors, N);
      EXPECT_NEAR(composite(group, colors).opacity, a, 1e-15) << "N " << N << " alpha " << a;
    }
}

TEST(OpacityCorrection, PartialGroupAimsAtItsShareOfTheUnitStep) {
  // m < N samples at the end of a ray aim at (1 - alpha_1)^(m/N): homogeneous -> Lacroute again.
  const int N = 8;
  for (int m : {1, 3, 7}) {
    std::vector<double> group(m, 0.6);
    correct_group(Correction::lee_newman, group, {}, N);
    for (double g : group) EXPECT_NEAR(g, lacroute(0.6, N), 1e-15);
  }
}

TEST(OpacityCorrection, Figure4SingleVoxel) {
  // Fig. 4: unit sample D = 67.0, five oversamples D = 67.0, 69.2, 73.4, 78.6, 84.8 in one voxel;
  // alpha = colour = D / 255 (eq. 7 and the linear opacity transfer function).  The paper shows
  // the resulting opacities and intensities only in the figure; the text gives no numbers.
  const int N = 5;
  const double unit = 67.0 / 255;
  const std::vector<double> D{67.0, 69.2, 73.4, 78.6, 84.8};
  std::printf("Fig. 4 (N = 5): %-22s opacity %.6f  intensity %.6f\n", "unit sampling", unit, unit * unit);
  std::vector<CompositedRay> result;
  for (Correction c : kAll) {
    std::vector<double> a, col;
    for (double d : D) a.push_back(d / 255), col.push_back(d / 255);
    double p = 1;
    if (c == Correction::lee_newman || c == Correction::lee_newman_quadratic) p = corrected_p(c, a);
    correct_group(c, a, col, N);
    result.push_back(composite(a, col));
    std::printf("Fig. 4 (N = 5): %-22s opacity %.6f  intensity %.6f", std::string(correction_name(c)).c_str(),
                result.back().opacity, result.back().intensity);
    if (p != 1) std::printf("  p = %.10f", p);
    std::printf("\n");
  }
  const CompositedRay none = result[0], lac = result[1], sch = result[2], ln = result[3], lnq = result[4];
  EXPECT_NEAR(ln.opacity, unit, 1e-15);                         // the defining property
  EXPECT_GT(none.opacity, lac.opacity);                         // uncorrected over-composites ...
  EXPECT_GT(none.intensity, unit * unit);                       // ... opacity and intensity
  EXPECT_GT(lac.opacity, unit);                                 // samples grow: Lacroute > unit
  EXPECT_LT(lac.opacity, 1.5 * unit);                           // but limits the over-composition
  EXPECT_EQ(sch.opacity, lac.opacity);                          // same alphas, colours scaled
  EXPECT_LT(sch.intensity, lac.intensity);
  EXPECT_NEAR(lnq.opacity, unit, 0.02);                         // the fit: p off by ~0.008 here
}

struct FitError {
  double mean = 0, sd = 0, share_above = 0, max = 0;
  double mean_bound = 0;  // the mean of the derived per-group bounds
  long count = 0;
};

// The fit's error, derived.  F(p) = prod_k (1 - p a_k) - (1 - alpha_unit) is a polynomial in p with
// |F'''| <= 6 e_3(a) on [0, 1] (e_3 the third elementary symmetric polynomial: every term of F'''
// is -6 a_i a_j a_l times factors in [0, 1]); the quadratic F^ through p = 0, 1/2, 1 therefore
// differs from F by at most e_3 |p (p - 1/2) (p - 1)| (the interpolation remainder).  At the
// fit's root F^(p^) = 0, so
//   |F(p^)| <= e_3 |w(p^)|,  w(p) = p (p - 1/2) (p - 1),                      (resultant opacity)
// and, F being convex and decreasing (|F'| falls with p),
//   |p^ - p| <= |F(p^)| / |F'(max(p, p^))|.                                   (the fitted p)
// A slack of 1e-13 in F covers rounding (the products of N <= 64 factors).
double elementary_3(std::span<const double> a) {
  double e1 = 0, e2 = 0, e3 = 0;  // running e_1, e_2, e_3 of the prefix
  for (double x : a) {
    e3 += x * e2;
    e2 += x * e1;
    e1 += x;
  }
  return e3;
}

double fit_residual_bound(std::span<const double> a, double p_fit) {
  return elementary_3(a) * std::fabs(p_fit * (p_fit - 0.5) * (p_fit - 1)) + 1e-13;
}

double fit_p_bound(std::span<const double> a, double p_exact, double p_fit) {
  const double q = std::max(p_exact, p_fit);
  double slope = 0;  // |F'(q)| = sum_k a_k prod_{m != k} (1 - q a_m)
  for (std::size_t k = 0; k < a.size(); ++k) {
    double term = a[k];
    for (std::size_t m = 0; m < a.size(); ++m)
      if (m != k) term *= 1 - q * a[m];
    slope += term;
  }
  return slope > 0 ? fit_residual_bound(a, p_fit) / slope : std::numeric_limits<double>::infinity();
}

template <class MakeGroup>
FitError fit_error(long count, int N, MakeGroup make) {
  std::vector<double> errors;
  errors.reserve(count);
  std::vector<double> a(N);
  double bound_sum = 0;
  long over_bound = 0;
  for (long i = 0; i < count; ++i) {
    make(i, a);
    const double exact = lee_newman_p(a, a[0]), quad = lee_newman_quadratic_p(a, a[0]);
    EXPECT_TRUE(std::isfinite(quad));
    EXPECT_GE(quad, 0);
    EXPECT_LE(quad, 1);
    errors.push_back(std::fabs(quad - exact));
    const double bound = fit_p_bound(a, exact, quad);
    bound_sum += std::min(bound, 1.0);  // p and p^ are both in [0, 1]
    if (!(errors.back() <= bound)) ++over_bound;
  }
  EXPECT_EQ(over_bound, 0) << "groups whose fit error exceeds the derived bound (N = " << N << ")";
  FitError f;
  f.count = count;
  f.mean_bound = bound_sum / static_cast<double>(count);
  for (double e : errors) f.mean += e, f.max = std::max(f.max, e), f.share_above += e > 0.1;
  f.mean /= count;
  for (double e : errors) f.sd += (e - f.mean) * (e - f.mean);
  f.sd = std::sqrt(f.sd / count);
  f.share_above /= count;
  return f;
}

void print(const char* what, const FitError& f) {
  std::printf("quadratic fit |p_quad - p_exact|, %-40s mean %.3g  sd %.3g  above 0.1: %.3f %%  max %.3g  (%ld groups)\n",
              what, f.mean, f.sd, 100 * f.share_above, f.max, f.count);
}

TEST(OpacityCorrection, QuadraticFitErrorOnEightBitData) {
  // The paper (sec. 4.4): mean 0.0031, sd 0.012, 0.09 % above 0.1, for N = 5 on the lobster data.
  // For N = 2 eq. 10 is itself a quadratic, so the fit through three points is exact and the
  // error is rounding only.
  const FitError n2 = fit_error(256 * 256, 2, [](long i, std::vector<double>& a) {
    a[0] = (i / 256) / 255.0;
    a[1] = (i % 256) / 255.0;
  });
  print("N = 2, all 8-bit pairs:", n2);
  EXPECT_LT(n2.max, 1e-9);  // e_3 = 0: the fit is exact up to rounding for N = 2

  // N = 5 has no exhaustive 8-bit universe; two synthetic stand-ins for the paper's lobster data.
  const FitError ramps = fit_error(256 * 256, 5, [](long i, std::vector<double>& a) {
    const double d0 = static_cast<double>(i / 256), d1 = static_cast<double>(i % 256);
    for (int k = 0; k < 5; ++k) a[k] = (d0 + (d1 - d0) * k / 5) / 255;  // linear along the voxel
  });
  print("N = 5, linear ramps between 8-bit values:", ramps);
  std::mt19937_64 rng(4);
  std::uniform_int_distribution<int> byte(0, 255);
  const FitError iid = fit_error(100000, 5, [&](long, std::vector<double>& a) {
    for (double& x : a) x = byte(rng) / 255.0;
  });
  print("N = 5, independent random 8-bit samples:", iid);
  // Every group is within its derived bound (checked in fit_error), so the means are too; the
  // bound is informative: its mean is below 0.1 on both sets.
  EXPECT_LE(ramps.mean, ramps.mean_bound);
  EXPECT_LE(iid.mean, iid.mean_bound);
  EXPECT_LT(ramps.mean_bound, 0.1) << ramps.mean_bound;
  EXPECT_LT(iid.mean_bound, 0.1) << iid.mean_bound;
  // Beyond N = 5 the fit degrades (the paper stops at 5) but stays within its bound.
  for (int N : {8, 16, 64}) {
    std::mt19937_64 r(N);
    const FitError f = fit_error(20000, N, [&](long, std::vector<double>& a) {
      for (double& x : a) x = byte(r) / 255.0;
    });
    print(N == 8 ? "N = 8, independent random 8-bit samples:" : N == 16 ? "N = 16, ...:" : "N = 64, ...:", f);
  }
}

TEST(OpacityCorrection, EdgeCasesStayFiniteAndInRange) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (int N : {1, 2, 3, 5, 1024}) {
    std::vector<std::vector<double>> groups;
    groups.push_back(std::vector<double>(N, 0.0));
    groups.push_back(std::vector<double>(N, 1.0));
    std::vector<double> g(N);
    for (int k = 0; k < N; ++k) g[k] = k % 2;  // 0, 1, 0, 1, ...
    groups.push_back(g);
    for (int k = 0; k < N; ++k) g[k] = 1 - k % 2;  // 1, 0, 1, 0, ...
    groups.push_back(g);
    g.assign(N, 0.0), g[N - 1] = 1;  // transparent unit sample, opaque last
    groups.push_back(g);
    g.assign(N, 1e-300), g[0] = 0.5;
    groups.push_back(g);
    g.assign(N, 1 - 0x1p-53), g[0] = 1e-300;
    groups.push_back(g);
    g.assign(N, 0.5), g[0] = 1 - 0x1p-53;
    groups.push_back(g);
    g.assign(N, 1.0), g[0] = 0.5;
    groups.push_back(g);
    g.assign(N, 0.3), g[0] = nan, g[N - 1] = -2;  // garbage in: clamped, NaN read as 0
    groups.push_back(g);
    g.assign(N, inf), g[0] = 0.7;
    groups.push_back(g);
    for (const auto& group : groups)
      for (Correction c : kAll) {
        std::vector<double> a = group, col(N, 0.8);
        correct_group(c, a, col, N);
        for (int k = 0; k < N; ++k) {
          const bool garbage = !(group[k] >= 0 && group[k] <= 1);
          if (c == Correction::none && garbage) continue;  // none leaves the input as it is
          ASSERT_TRUE(std::isfinite(a[k])) << correction_name(c) << " N " << N;
          ASSERT_GE(a[k], 0) << correction_name(c) << " N " << N;
          ASSERT_LE(a[k], 1) << correction_name(c) << " N " << N;
          ASSERT_TRUE(std::isfinite(col[k])) << correction_name(c) << " N " << N;
        }
        if (c == Correction::lee_newman || c == Correction::lee_newman_quadratic) {
          const double p = corrected_p(c, group);
          ASSERT_TRUE(p >= 0 && p <= 1) << correction_name(c) << " N " << N;
        }
      }
  }
}

TEST(OpacityCorrection, EdgeConventionsForP) {
  for (Correction c : {Correction::lee_newman, Correction::lee_newman_quadratic}) {
    const auto p = [c](std::vector<double> a) { return corrected_p(c, a); };
    EXPECT_EQ(p({0, 0, 0}), 1.0);              // all zero: any p; we keep 1
    EXPECT_EQ(p({0, 0.5, 1}), 0.0);            // transparent unit sample: the voxel is transparent
    EXPECT_EQ(p({1, 0.2, 0.7}), 1.0);          // opaque unit sample: only p = 1 reaches 0
    EXPECT_EQ(p({0.4}), 1.0);                  // N = 1
    EXPECT_EQ(p({0.4, 0, 0, 0}), 1.0);         // root exactly at 1
    EXPECT_EQ(lee_newman_p(std::vector<double>{0, 0}, 0.5), 1.0);  // no root: clamp to 1
    EXPECT_EQ(lee_newman_quadratic_p(std::vector<double>{0.1, 0.1}, 0.9), 1.0);
  }
  // alpha_k = 1 inside: (1 - p/2)(1 - p) = 1/2  ->  p = (3 - sqrt 5) / 2.
  EXPECT_NEAR(lee_newman_p(std::vector<double>{0.5, 1.0}, 0.5), (3 - std::sqrt(5.0)) / 2, 1e-16);
  EXPECT_NEAR(lee_newman_quadratic_p(std::vector<double>{0.5, 1.0}, 0.5), (3 - std::sqrt(5.0)) / 2, 1e-15);
  // Eq. 10 solved by hand for (0.2, 0.6): 0.12 p^2 - 0.8 p + 0.2 = 0.
  const double root = (0.8 - std::sqrt(0.64 - 4 * 0.12 * 0.2)) / (2 * 0.12);
  EXPECT_NEAR(lee_newman_p(std::vector<double>{0.2, 0.6}, 0.2), root, 1e-15);
  EXPECT_NEAR(lee_newman_quadratic_p(std::vector<double>{0.2, 0.6}, 0.2), root, 1e-15);
  // N = 1 leaves everything as it is, for every correction.
  for (Correction c : kAll) {
    std::vector<double> a{0.37}, col{0.9};
    correct_group(c, a, col, 1);
    EXPECT_EQ(a[0], 0.37) << correction_name(c);
    EXPECT_EQ(col[0], 0.9) << correction_name(c);
  }
}

}  // namespace
}  // namespace vrv

namespace vrv {
namespace {

// Centred oversamples straddle the unit sample: the group must aim at the opacity given for it,
// not at its first oversample.  (Opacity rising 0.2 -> 0.8 over the step, 0.5 at its centre.)
TEST(OpacityCorrection, LeeNewmanAimsAtTheGivenUnitOpacity) {
  for (int N : {3, 5, 63}) {
    std::vector<double> alphas(N), colors;
    for (int k = 0; k < N; ++k) alphas[k] = 0.2 + 0.6 * (k + 0.5) / N;
    for (Correction c : {Correction::lee_newman, Correction::lee_newman_quadratic}) {
      std::vector<double> a = alphas;
      correct_group(c, a, colors, N, 0.5);
      double log_t = 0;
      for (double x : a) log_t += std::log1p(-x);
      const double resultant = -std::expm1(log_t);
      if (c == Correction::lee_newman) {
        EXPECT_NEAR(resultant, 0.5, 1e-14) << N;
      } else {  // the fit's own error, derived (fit_residual_bound): |F(p^)| is the transparency's
        const double p_fit = a[0] / alphas[0];
        EXPECT_NEAR(resultant, 0.5, fit_residual_bound(alphas, p_fit)) << N;
        if (N <= 5) {  // informative: 0.051 at N = 5
          EXPECT_LT(fit_residual_bound(alphas, p_fit), 0.1) << N;
        }
      }
      std::vector<double> first = alphas;
      correct_group(c, first, colors, N);  // default: the first oversample is the unit sample
      double log_first = 0;
      for (double x : first) log_first += std::log1p(-x);
      if (c == Correction::lee_newman) {
        EXPECT_NEAR(-std::expm1(log_first), alphas[0], 1e-14) << N;
      }
    }
  }
}

}  // namespace
}  // namespace vrv
