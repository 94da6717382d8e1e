#pragma once
// The images a verification reads, checked before any work is done.
#include <string>
#include <vector>

#include "lib/io/image_channels.h"
#include "lib/verify/verify_options.h"

namespace vrv {

// A renderer's image and the sample distance (world units) it was rendered with.
struct ImageWithStep {
  std::string name;  // the file, or a label: every message names it
  double step = 0;
  ChannelImage image;
};

// VerifyInputError for bad images (none, different sizes or channel counts, a non-positive or
// repeated step, non-finite pixels unless options.allow_nan), std::invalid_argument naming the
// option for bad options.
void check_inputs(const std::vector<ImageWithStep>& images, const VerifyOptions& options);

// The images by decreasing step (the order of every report), ties in their given order.
std::vector<const ImageWithStep*> sorted_by_step(const std::vector<ImageWithStep>& images);

// The value channel c of pixel i stands for, comparable with the reference: colour composited
// over the background (after multiplying by alpha for straight colour), or the alpha itself.
double comparable(const ChannelImage& image, int c, std::size_t i, double background, AlphaMode mode);

// The first channel that is not alpha; the channel count when there is none.
int first_colour_channel(const ChannelImage& image);

}  // namespace vrv
