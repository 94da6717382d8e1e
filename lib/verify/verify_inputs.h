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
// option for bad options (OptionError for options.alpha other than auto on images without alpha:
// it would be ignored).
void check_inputs(const std::vector<ImageWithStep>& images, const VerifyOptions& options);

// The images by decreasing step (the order of every report), ties in their given order.
std::vector<const ImageWithStep*> sorted_by_step(const std::vector<ImageWithStep>& images);

// The value channel c of pixel i stands for, comparable with the reference: colour composited
// over the background (after multiplying by alpha for straight colour), or the alpha itself.
double comparable(const ChannelImage& image, int c, std::size_t i, double background, AlphaMode mode);

// The scene channel each channel of `image` is judged against (alpha: 0, its truth the shared
// optical depth).  A grey scene: 0 for every channel.  An RGB scene needs exactly three colour
// channels: named R, G and B (or red, green, blue; any order, any case, after the last '.' of a
// layer name) they are matched by name, otherwise taken in order as red, green and blue.
// VerifyInputError naming the image for another count of colour channels.
std::vector<int> reference_channels(const ImageWithStep& image, int scene_channels);

// The first channel that is not alpha; the channel count when there is none.
int first_colour_channel(const ChannelImage& image);

}  // namespace vrv
