#pragma once
// Colour channels in the wrong order: an RGB image whose channels match the reference far better
// in another order (a BGR framebuffer written as RGB, a swizzle in a shader) is named, with the
// order it matches.
#include <optional>
#include <vector>

#include "lib/scene.h"
#include "lib/verify/reference_image.h"
#include "lib/verify/verify_inputs.h"
#include "lib/verify/verify_report.h"

namespace vrv {

// Every order of `image`'s three colour channels against the RGB scene's three references
// (`truth`: reference_channels of the image, `references` one per scene channel).  A fault when
// another order's RMS error is under a quarter of the given order's and the given order's is
// above twice the image's quantisation floor: a correct renderer's discretisation error cannot
// make another order match four times better unless its channels' differences are below its
// error, where an order means nothing.
std::optional<Fault> swapped_channels(const ImageWithStep& image, const std::vector<int>& truth,
                                      const std::vector<ReferenceImage>& references, const ColorChannels& color,
                                      AlphaMode alpha);

}  // namespace vrv
