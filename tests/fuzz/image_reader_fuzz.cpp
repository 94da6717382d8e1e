// Fuzz target: an image as `vrv verify` reads it (read_channel_image and read_provenance,
// lib/io/image_channels.h, lib/io/image_io.h; PNG, EXR, PFM and TIFF through OpenImageIO's module,
// .npy by lib/io/npy).  The first byte picks the file's extension, the rest are its bytes.  Any
// input gives an image whose pixels match its size and channels and whose quantum is finite and
// non-negative, or one std::runtime_error line naming the file; never a crash, a hang or a leak.
// EXR and PNG headers claiming more than kMaxImagePixels are skipped (tests/fuzz/fuzz_limits.h).
// The module is found through VRV_IMAGE_MODULE (set by CTest).
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <string_view>

#include "lib/io/image_channels.h"
#include "lib/io/image_io.h"

#include "tests/fuzz/fuzz_limits.h"

namespace fs = std::filesystem;

namespace {

constexpr std::array<const char*, 6> kExtensions = {".png", ".exr", ".pfm", ".npy", ".tif", ".png"};

void check_one_line(const std::string& msg, const std::string& file) {
  if (msg.rfind(file, 0) == 0 && msg.find('\n') == std::string::npos && msg.size() <= 2000) return;
  std::fprintf(stderr, "not one line naming the file: %s\n", msg.c_str());
  std::abort();
}

void check_image(const vrv::ChannelImage& im) {
  if (im.width < 1 || im.height < 1 || im.names.size() != static_cast<std::size_t>(im.channels) || im.channels < 1 ||
      im.channels > 4)
    std::abort();
  if (im.pixels.size() != im.pixel_count() * im.channels) std::abort();
  if (im.alpha >= im.channels) std::abort();
  const double q = vrv::effective_quantum(im);
  if (!(q >= 0) || !std::isfinite(q)) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static const fs::path dir = [] {
    const fs::path d = vrv::fuzz::scratch_root() / ("vrv-fuzz-image-" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
  }();
  const std::string_view body(reinterpret_cast<const char*>(data + 1), size - 1);
  if (vrv::fuzz::claimed_image_pixels(body) > vrv::fuzz::kMaxImagePixels) return 0;  // a large image's cost
  const fs::path file = dir / (std::string("image") + kExtensions[data[0] % kExtensions.size()]);
  std::ofstream(file, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  try {
    check_image(vrv::read_channel_image(file));
  } catch (const std::runtime_error& e) {
    check_one_line(e.what(), file.string());
  }
  try {
    vrv::read_provenance(file);
  } catch (const std::runtime_error& e) {
    check_one_line(e.what(), file.string());
  }
  return 0;
}
