#pragma once
// One ray's projection reference (lib/projection/xray_reference.h, mip_reference.h).
#include <limits>

namespace vrv {

struct ProjectionOptions {
  double tol = 1e-12;  // absolute tolerance on the value
};

struct ProjectionResult {
  double value = 0;           // the integral (X-ray) or the maximum (MIP); 0 for a ray that misses
  double error_estimate = 0;  // bound on |exact - value|
  long evaluations = 0;       // field evaluations
  bool hit = false;           // the ray meets the box
  double t_entry = 0;         // clipped range (world length along the unit direction)
  double t_exit = 0;
  // MIP: the ray parameter t of the maximum, the first one where values tie within the field's
  // rounding (a plateau: its start); NaN for X-ray and for a ray that misses.
  double position = std::numeric_limits<double>::quiet_NaN();
  // MIP: another maximum, separated from `position` by a dip, comes within error_estimate of the
  // value, so the position may be the other one (the value is still within the estimate).
  bool ambiguous = false;
  // The estimate is within the tolerance, finite, and no work cap was reached.
  bool tolerance_met = true;
};

}  // namespace vrv
