#include "analytic/marschner_lobb.h"

#include <cmath>

namespace vrv {

double MarschnerLobb::value(const Vec3& p) const {
  constexpr double pi = std::numbers::pi;
  const double r = std::hypot(p.x(), p.y());
  const double rho_r = std::cos(2 * pi * fM * std::cos(pi * r / 2));
  return (1 - std::sin(pi * p.z() / 2) + alpha * (1 + rho_r)) / (2 * (1 + alpha));
}

}  // namespace vrv
