#pragma once
// f(x) = offset + dot(gradient, x): linear along every ray, so with a piecewise-linear
// transfer function every piece of a ray has a closed form.
#include <vector>

#include "analytic/vec3.h"

namespace vrv {

struct LinearRamp {
  Vec3 gradient{1, 0, 0};
  double offset = 0;

  double value(const Vec3& p) const { return offset + gradient.dot(p); }
  int degree_along_ray() const { return 1; }
  double bandwidth() const { return 0; }
  // Smooth everywhere: no breaks on any ray (any ray and interval types).
  void append_breaks(const auto&, const auto&, std::vector<double>&) const {}
};

}  // namespace vrv
