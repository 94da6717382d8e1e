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
    Vec3 o(normal(rng), normal(rng), normal(rng));
    o = 3 * o.normalized();
    const Vec3 target(box(rng), box(rng), box(rng));
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
