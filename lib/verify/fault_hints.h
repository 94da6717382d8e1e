#pragma once
// The known faults whose pattern a verification's errors match: quantisation, a half-step offset,
// a constant floor, a first-order border band, jitter, error at transfer-function jumps, a
// missing opacity correction and a shaded image's gradient floor, each with one sentence of evidence.
#include <vector>

#include "lib/verify/pixel_geometry.h"
#include "lib/verify/verify_options.h"
#include "lib/verify/verify_report.h"

namespace vrv {

// From a report with its channels, orders and diagnosis filled in (`channel_count` channels per
// image), read on channel `colour` (the diagnosed one), whose pixels' geometry is `geometry`.
std::vector<Fault> find_faults(const VerifyReport& report, const PixelGeometry& geometry, int channel_count,
                               int colour, const VerifyOptions& options);

}  // namespace vrv
