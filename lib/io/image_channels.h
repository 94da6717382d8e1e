#pragma once
// A renderer's image as vrv verify reads it: every channel in double, with the names, which one
// is alpha, and how finely the file could store a value (its quantum), so that an 8- or 16-bit
// image's rounding is stated instead of being mistaken for a discretisation error.
#include <cmath>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "lib/io/image_io.h"

namespace vrv {

// The pixels are an ImageF64's (interleaved, row 0 at the top: value(i, c)); the rest is what the
// file says of them.
struct ChannelImage : ImageF64 {
  std::vector<std::string> names;  // e.g. {"R", "G", "B", "A"} or {"Y"}
  int alpha = -1;                  // index of the alpha channel, -1 without one
  // The file declares its colour straight (not premultiplied by alpha: PNG, a TIFF with
  // unassociated alpha) and it was read as stored; AlphaMode::as_stored then takes it straight.
  bool straight_alpha = false;
  std::string pixel_type;                   // "uint8", "uint16", "half", "float", "double", ...
  // Spacing of the stored values near the image's largest magnitude: 1/255 (uint8), 1/65535
  // (uint16) as OpenImageIO scales them to [0, 1]; for floating types one ulp at the largest
  // |value| (half: 2^-10 relative, float: 2^-23, double: 2^-52).  Rounding to the nearest
  // stored value is then uniform on +-quantum/2: max error quantum/2, RMS quantum/sqrt(12).
  double quantum = 0;

  ChannelImage() = default;
  // `pixels` with its channels' names (channel_names() of its count when empty) and alpha: the
  // first channel named "A", "a" or "alpha", else the last of two or four (YA, RGBA by position).
  explicit ChannelImage(ImageF64 pixels, std::vector<std::string> channel_names = {});
};

// The quantum a ChannelImage of `pixel_type` ("uint8", "uint16", "half", "float", "double", ...)
// gets at its largest |value| `largest`: an image made in memory (a gate's render) as if written
// in that type.  std::invalid_argument for a type the readers do not know.
double stored_quantum(const std::string& pixel_type, double largest);

// Reads the first subimage of anything OpenImageIO reads (EXR, TIFF, PFM, PNG, ...), 1 to 4
// channels, or a numpy .npy array (float32 or float64, (height, width) or (height, width, 1..4)).  Throws std::runtime_error, one line naming the file and the reason, when it cannot
// be read, is deep, volumetric, empty, larger than 65536 on a side or has more than 4 channels.
ChannelImage read_channel_image(const std::filesystem::path& path);

struct NpyArray;
// The same from a numpy array in memory (vrv.verify's arrays, as a .npy file would hold them):
// the channel names, alpha and quantum a .npy file of that shape and dtype gets; the errors are
// one line "<name>: <reason>".
ChannelImage channel_image(const NpyArray& array, const std::string& name);

// The quantum `image`'s values show: its stored quantum, unless every finite value (at least 16
// distinct ones) sits on a multiple of 1/255 or 1/65535 to within float32 rounding, whatever the
// stored type: an 8- or 16-bit framebuffer saved as float (or passed as an array) has the floor
// of its integers, not of the float it was stored in.
double effective_quantum(const ChannelImage& image);

}  // namespace vrv
