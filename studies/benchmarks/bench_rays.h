#pragma once
// Benchmark support: the rays and transfer functions the benchmarks share.
#include <cstdint>
#include <random>
#include <vector>

#include "lib/geometry.h"
#include "lib/transfer_function.h"

namespace vrv::bench {

// Origins on a sphere of radius 3 aimed at uniform points in [-1, 1]^3; fixed seed.
inline std::vector<Ray> random_rays(int count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> box(-1, 1);
  std::vector<Ray> rays;
  for (int i = 0; i < count; ++i) {
    // One draw per statement: the order of a call's arguments is unspecified (GCC evaluates them
    // last to first, Clang first to last), and the sanitized Clang build ran the tests on other
    // rays.  These are GCC's order, so the rays every earlier result was measured on are kept.
    const double oz = normal(rng);
    const double oy = normal(rng);
    const double ox = normal(rng);
    const Vec3 o = 3 * Vec3(ox, oy, oz).normalized();
    const double tz = box(rng);
    const double ty = box(rng);
    const double tx = box(rng);
    const Vec3 target(tx, ty, tz);
    rays.push_back(make_ray(o, target - o));
  }
  return rays;
}

// Emission not proportional to extinction, with kinks at six control values, so the
// reference takes its general (nested) route.
inline TransferFunction nonproportional_tf() {
  return TransferFunction::emission_extinction(
      PiecewiseLinear({{0, 0}, {0.3, 0.1}, {0.5, 1.0}, {0.7, 0.2}, {1, 0.5}}),
      PiecewiseLinear({{0, 0}, {0.4, 0.8}, {1, 0.3}}));
}

}  // namespace vrv::bench
