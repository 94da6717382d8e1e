#pragma once
// The point type of the analytic fields: Eigen's 3-vector.  lib/geometry.h's Vec3 is this alias,
// so analytic/ needs nothing from lib/ (lib/ includes analytic/, never the reverse).
#include <Eigen/Core>

namespace vrv {

using Vec3 = Eigen::Vector3d;

}  // namespace vrv
