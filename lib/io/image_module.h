#pragma once
// The image library (OpenImageIO) is loaded only by the processes that read or write an image:
// it brings ~260 shared libraries, 0.5 s of dynamic loading that `vrv ray` or `vrv --help` should
// not pay.  It lives in a module of its own (lib/io/image_module_oiio.cpp, built as
// libvrv_image.so) that image_module::functions() loads with dlopen() on first use.
//
// The module and vrv are built together by the same compiler, so the interface is plain C++;
// kAbiVersion guards against a module left over from another build of this interface.  Errors
// cross it as strings (never exceptions): "" means success, anything else is a one-line reason.
#include <filesystem>
#include <future>
#include <string>
#include <utility>
#include <vector>

namespace vrv::image_module {

inline constexpr int kAbiVersion = 4;
// The C symbol the module exports: a `const Functions*`-returning function.
inline constexpr const char* kEntrySymbol = "vrv_image_module_functions";

enum class PixelType { float32, float64, uint8 };

struct WriteRequest {
  std::string format;  // OpenImageIO writer name: "openexr", "png"
  int width = 0, height = 0, channels = 1;
  PixelType type = PixelType::float32;
  const void* pixels = nullptr;  // row-major, channels interleaved, row 0 = top
  std::vector<std::string> channel_names;  // empty: the writer's default names
  std::vector<std::pair<std::string, std::string>> attributes;  // e.g. {"compression", "zip"}
};

// What to read: the header always; when `pixels` is set, the pixels of a 2D image with 1 to
// max_channels channels (interleaved), converted to `type` (float32 or float64), refused above
// max_side or max_pixels before anything is allocated.
struct ReadRequest {
  bool pixels = true;
  PixelType type = PixelType::float32;
  int max_channels = 1;  // 1: one-channel images only; 4: grey, grey+alpha, RGB or RGBA
  int max_side = 1 << 16;
  long long max_pixels = 1LL << 28;
  // Colour a file stores unassociated from alpha (straight: PNG; TIFF with unassociated extra
  // samples) read as stored; otherwise OpenImageIO premultiplies it on reading.
  bool keep_straight_alpha = false;
};

struct ReadResult {
  int width = 0, height = 0, depth = 1, channels = 0;
  bool deep = false;
  std::string format_name;  // the reader: "openexr", "png", "tiff", ...
  std::string pixel_type;   // as stored: "float", "uint8", "double", ...
  bool floating = false;    // the stored type is floating point
  int bits = 0;             // bits per sample as stored
  std::vector<std::string> channel_names;  // as stored (may be empty or shorter than channels)
  int alpha_channel = -1;                   // the reader's alpha channel, -1 when it names none
  bool straight_alpha = false;  // keep_straight_alpha and the file stores straight colour (as read)
  std::vector<std::pair<std::string, std::string>> attributes;  // every metadata item, as text
  std::vector<float> floats;    // the pixels, when read as float32
  std::vector<double> doubles;  // the pixels, when read as float64
};

struct Functions {
  int abi_version = kAbiVersion;
  // Writes the request to `path` (the caller handles temporary names and renaming).
  std::string (*write)(const std::string& path, const WriteRequest& request) = nullptr;
  // Reads the first subimage's header and, as asked, its pixels.
  std::string (*read)(const std::string& path, const ReadRequest& request, ReadResult& out) = nullptr;
};

// The loaded module's functions.  Looks for the module at $VRV_IMAGE_MODULE when that is set
// (and nowhere else), otherwise next to the program (or Python module) running, then in the
// install library directory relative to it (<prefix>/lib/vrv, lib/util/install_dirs.h), then in
// the configured install prefix's, then (only for code running from it) the build tree's.
// Throws std::runtime_error with one line naming where it looked when it cannot be loaded.
const Functions& functions();

// Loads the module on a thread of its own while the caller computes: a render overlaps the 0.3 to
// 0.5 s of dynamic loading instead of waiting for it.  A module found nowhere is refused here, at
// once and with functions()'s message, so a render does not run for nothing; one that is found but
// cannot be loaded is reported by wait().  The destructor waits for the load.
class BackgroundLoad {
 public:
  BackgroundLoad();
  ~BackgroundLoad();
  BackgroundLoad(const BackgroundLoad&) = delete;
  BackgroundLoad& operator=(const BackgroundLoad&) = delete;
  // The module loaded; throws its load error (std::runtime_error, one line).
  void wait();

 private:
  std::future<void> load_;
};

// Reads `path` with the loaded module as `request` asks.  Throws std::runtime_error, one line
// "<path>: <reason>", when the file is missing, a directory, or the module refuses it.
ReadResult read_file(const std::filesystem::path& path, const ReadRequest& request);

}  // namespace vrv::image_module
