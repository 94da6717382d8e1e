#pragma once
// Error-free transformations: the rounding error of one floating-point operation, exactly.
// Needs IEEE semantics (no -ffast-math; see CMakeLists.txt).
namespace vrv {

// Knuth's TwoSum: s = fl(a + b) and e with a + b = s + e exactly.
inline void two_sum(double a, double b, double& s, double& e) {
  s = a + b;
  const double bb = s - a;
  e = (a - (s - bb)) + (b - bb);
}

// The exact rounding error of fl(a + b).
inline double sum_rounding(double a, double b) {
  double s = 0, e = 0;
  two_sum(a, b, s, e);
  return e;
}

}  // namespace vrv
