#pragma once
// Across a channel's images: the observed order against the reference and the self-convergence
// order (differences of successive images), each judged, and the verification's verdict (the
// worst channel's).
#include <string>
#include <vector>

#include "lib/verify/verify_inputs.h"
#include "lib/verify/verify_report.h"

namespace vrv {

// Fills report.orders (per channel: reference, then self), report.verdict and verdict_channel
// from report.channels (image-major over `sorted`, then channel), and adds a failure when an
// expected order is missed.  The channels are named `names` (the first image's as given); channel
// c is composited over backgrounds[c] (its scene channel's background).
void judge_orders(VerifyReport& report, const std::vector<const ImageWithStep*>& sorted,
                  const std::vector<std::string>& names, const std::vector<double>& backgrounds,
                  const VerifyOptions& options);

}  // namespace vrv
