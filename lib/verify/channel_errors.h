#pragma once
// One image channel's signed error against the reference, its statistics over the whole image
// and each region, and its quantisation floor; and the difference of two images' channel (the
// self-convergence order's points).
#include "lib/verify/pixel_geometry.h"
#include "lib/verify/reference_image.h"
#include "lib/verify/verify_inputs.h"
#include "lib/verify/verify_report.h"

namespace vrv {

ChannelReport channel_report(const ImageWithStep& image, int channel, const ReferenceImage& ref,
                             const PixelGeometry& geometry, double background, const VerifyOptions& options);

// The order metric (options.order_metric) of the difference between two images' channel.
double difference_metric(const ChannelImage& a, const ChannelImage& b, int channel, double background,
                         const VerifyOptions& options);

}  // namespace vrv
