// Marschner-Lobb's local frequency bound (bandwidth_between), which sizes the reference
// integrator's first panels: it must bound the field's instantaneous angular frequency along the
// segment (sampled densely here from the analytic derivative of each term's phase), never exceed
// the global bound, and only grow with the segment (up to rounding; the integrator's merge search
// is then optimal, and every merge it makes was checked on its own).
#include "analytic/marschner_lobb.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>

namespace vrv {
namespace {

constexpr double pi = std::numbers::pi;

double uniform(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1p-53; }

// The largest |d/dt| of the two phases, 2 pi fM cos(pi r / 2) and pi z / 2 (through sin), over
// `samples` points of the segment p -> q.
double sampled_frequency(const MarschnerLobb& ml, const Vec3& p, const Vec3& q, int samples) {
  const Vec3 u = (q - p).normalized();
  double most = 0;
  for (int i = 0; i <= samples; ++i) {
    const Vec3 x = p + (q - p) * (static_cast<double>(i) / samples);
    const double r = std::hypot(x.x(), x.y());
    const double dr = r > 0 ? (x.x() * u.x() + x.y() * u.y()) / r : 0;
    const double radial = pi * pi * ml.fM * std::abs(std::sin(pi * r / 2) * dr);
    const double axial = pi / 2 * std::abs(std::cos(pi * x.z() / 2) * u.z());
    most = std::max(most, radial + axial);
  }
  return most;
}

TEST(MarschnerLobb, LocalBandwidthBoundsTheFrequencyOnTheSegment) {
  std::mt19937_64 rng(10);
  for (double fM : {6.0, 24.0}) {
    const MarschnerLobb ml{fM, 0.25};
    for (int i = 0; i < 2000; ++i) {
      Vec3 p(6 * uniform(rng) - 3, 6 * uniform(rng) - 3, 6 * uniform(rng) - 3);
      Vec3 d(2 * uniform(rng) - 1, 2 * uniform(rng) - 1, 2 * uniform(rng) - 1);
      if (i % 4 == 0) p.x() = p.y() = 0;                 // starting on the axis
      if (i % 4 == 1) d.x() *= 1e-3, d.y() *= 1e-3;      // nearly along it
      const double length = i % 3 == 0 ? 4 * uniform(rng) : 0.2 * uniform(rng);
      const Vec3 q = p + length * d.normalized();
      const double bound = ml.bandwidth_between(p, q);
      EXPECT_LE(sampled_frequency(ml, p, q, 1000), bound * (1 + 1e-9)) << i;
      EXPECT_LE(bound, ml.bandwidth()) << i;
      // A part of the segment never gets a larger bound (up to the rounding of its direction, which a short segment far from the origin magnifies).
      const Vec3 m = p + 0.37 * (q - p);
      EXPECT_LE(ml.bandwidth_between(p, m), bound * (1 + 1e-6)) << i;
      EXPECT_LE(ml.bandwidth_between(m, q), bound * (1 + 1e-6)) << i;
    }
  }
}

TEST(MarschnerLobb, LocalBandwidthAlongTheAxisIsTheZTerm) {
  // On the axis r = 0: only sin(pi z / 2) varies, at most pi / 2 rad per unit (global bound at
  // fM = 24: 238 rad per unit).
  const MarschnerLobb ml{24, 0.25};
  EXPECT_DOUBLE_EQ(ml.bandwidth_between({0, 0, -30}, {0, 0, 30}), pi / 2);
  // Between z = 0.5 and 0.9 |cos(pi z / 2)| falls from cos(pi / 4) to cos(0.45 pi).
  EXPECT_NEAR(ml.bandwidth_between({0, 0, 0.5}, {0, 0, 0.9}), pi / 2 * std::cos(pi / 4), 1e-8);
  // Across the axis in the xy plane: the radial term alone, from r up to 0.1.
  EXPECT_NEAR(ml.bandwidth_between({-0.1, 0, 1}, {0.1, 0, 1}), pi * pi * 24 * std::sin(pi * 0.05), 1e-6);
  // Where the segment holds r = 1 and moves radially, the global radial bound pi^2 fM.
  EXPECT_NEAR(ml.bandwidth_between({0.9, 0, 1}, {1.1, 0, 1}), pi * pi * 24, 1e-6);
  // A degenerate segment: the global bound.
  EXPECT_EQ(ml.bandwidth_between({0.3, 0.2, 0.1}, {0.3, 0.2, 0.1}), ml.bandwidth());
}

}  // namespace
}  // namespace vrv
