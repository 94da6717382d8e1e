#pragma once
// Convention versus fault: a placement or rule whose pattern the errors match (a half-step
// offset, first-order ends of the ray, jitter; fault_hints.h) is a fault only when it contradicts
// what the renderer is meant to do.  With an expected order K, one whose implied order reaches
// K - order_tolerance is the renderer's convention ("behaves like: samples at the start of each
// step — consistent with the expected order 1"), not a fault.
#include <vector>

#include "lib/verify/verify_options.h"
#include "lib/verify/verify_report.h"

namespace vrv {

// Whether `fault` is consistent with options.expected_order (false without one, or when the
// fault implies no order).
bool consistent_with_expected_order(const Fault& fault, const VerifyOptions& options);

// Moves the faults consistent with the expected order from report.faults to report.conventions.
void separate_conventions(VerifyReport& report, const VerifyOptions& options);

}  // namespace vrv
