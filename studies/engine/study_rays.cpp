#include "studies/engine/study_rays.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

namespace vrv {
namespace {

// Uniform in [0, 1) from the top 53 bits: the same on every platform.
double unit(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

}  // namespace

std::vector<Ray> study_rays(const Box& box, long count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const Vec3 centre = 0.5 * (box.min + box.max);
  const double radius = 3 * 0.5 * box.extent().norm();
  std::vector<Ray> rays;
  rays.reserve(static_cast<std::size_t>(count));
  for (long i = 0; i < count; ++i) {
    const double z = 2 * unit(rng) - 1;
    const double phi = 2 * std::numbers::pi * unit(rng);
    const double rho = std::sqrt(std::max(0.0, 1 - z * z));
    const Vec3 origin = centre + radius * Vec3(rho * std::cos(phi), rho * std::sin(phi), z);
    Vec3 target;
    for (int k = 0; k < 3; ++k) target[k] = box.min[k] + unit(rng) * (box.max[k] - box.min[k]);
    rays.push_back(make_ray(origin, target - origin));
  }
  return rays;
}

}  // namespace vrv
