#pragma once
// The studies' shared ray set: a fixed seed gives the same rays on every platform.
#include <cstdint>
#include <vector>

#include "lib/geometry.h"

namespace vrv {

// The fixed-seed ray set: origins uniform on the sphere of radius 3 x the box half-diagonal
// around the box centre, each aimed at a uniform point of the box.  Same rays on every platform
// (own conversion of mt19937_64 output, no std distributions).
std::vector<Ray> study_rays(const Box& box, long count, std::uint64_t seed);

}  // namespace vrv
