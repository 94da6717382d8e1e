#pragma once
// Closed forms for one piece of a ray on which emission g and extinction tau are constant or
// linear in the path length s in [0, L]:
//   emission      E = int_0^L g(s) exp(-int_0^s tau) ds      (not yet attenuated by what lies in front)
//   optical depth D = int_0^L tau(s) ds
// The composite over pieces is I = sum_i E_i exp(-sum_{j<i} D_j) + I0 exp(-sum D).
// These are the Williams & Max (1992) linear-segment integrals, written in erfcx / Dawson form
// so that they neither overflow nor cancel; see docs/reference-integrator.md.
namespace vrv {

struct PieceIntegral {
  double emission = 0;
  double optical_depth = 0;
};

// g and tau constant (tau >= 0).
PieceIntegral constant_piece(double length, double g, double tau);

// g and tau linear from (g0, tau0) at s = 0 to (g1, tau1) at s = L; tau0, tau1 >= 0.
PieceIntegral linear_piece(double length, double g0, double g1, double tau0, double tau1);

// -expm1(-x) / x, continuous at 0: the fraction of a homogeneous slab's emission that escapes.
double escape_fraction(double x);

}  // namespace vrv
