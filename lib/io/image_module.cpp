#include "lib/io/image_module.h"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

#include "lib/io/image_structure.h"
#include "lib/util/install_dirs.h"

// Set by CMake: the module's file name, the configured install directory and the build directory.
#ifndef VRV_IMAGE_MODULE_FILE
#define VRV_IMAGE_MODULE_FILE "libvrv_image.so"
#endif
#ifndef VRV_IMAGE_MODULE_INSTALL_DIR
#define VRV_IMAGE_MODULE_INSTALL_DIR ""
#endif
#ifndef VRV_IMAGE_MODULE_BUILD_DIR
#define VRV_IMAGE_MODULE_BUILD_DIR ""
#endif

namespace vrv::image_module {
namespace {

namespace fs = std::filesystem;

// Whether `dir` is `root` or under it.
bool inside(const fs::path& dir, const fs::path& root) {
  const fs::path rel = dir.lexically_relative(root);
  return !rel.empty() && *rel.begin() != "..";
}

std::vector<fs::path> candidates() {
  if (const char* explicit_path = std::getenv("VRV_IMAGE_MODULE"); explicit_path && *explicit_path)
    return {fs::path(explicit_path)};
  // Beside the program (the build tree), then where `cmake --install` puts it relative to the
  // running program or Python module (lib/util/install_dirs.h), so an install prefix can move.
  std::vector<fs::path> paths;
  for (const fs::path& dir : installed_dirs(InstalledDir::image_module))
    paths.push_back(dir / VRV_IMAGE_MODULE_FILE);
  // Programs built against the installed library live elsewhere: the configured install prefix.
  if (*VRV_IMAGE_MODULE_INSTALL_DIR)
    paths.push_back(fs::path(VRV_IMAGE_MODULE_INSTALL_DIR) / VRV_IMAGE_MODULE_FILE);
  // Last, for code running from the build tree it was compiled in (test binaries, build/python),
  // that tree's module; an installed copy never falls back to a build tree.
  if (*VRV_IMAGE_MODULE_BUILD_DIR) {
    const fs::path build = fs::weakly_canonical(VRV_IMAGE_MODULE_BUILD_DIR);
    for (const OwnDir& own : own_dirs())
      if (inside(own.dir, build)) {
        paths.push_back(build / VRV_IMAGE_MODULE_FILE);
        break;
      }
  }
  return paths;
}

// The first candidate that is a file; else throws the message naming every place looked at.
fs::path locate() {
  std::string tried;
  for (const fs::path& path : candidates()) {
    std::error_code ec;
    if (fs::is_regular_file(path, ec)) return path;
    tried += fmt::format("{}{} (missing)", tried.empty() ? "" : ", ", path.string());
  }
  throw std::runtime_error(fmt::format(
      "image I/O: the image module {} was not found (looked at {}; set VRV_IMAGE_MODULE to its path)",
      VRV_IMAGE_MODULE_FILE, tried));
}

const Functions* load() {
  const fs::path path = locate();
  // RTLD_LOCAL: OpenImageIO's dependencies stay out of vrv's own symbol lookups.
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* why = dlerror();
    throw std::runtime_error(fmt::format("image I/O: cannot load the image module {}: {}", path.string(),
                                         why ? why : "unknown reason"));
  }
  using Entry = const Functions* (*)();
  const auto entry = reinterpret_cast<Entry>(dlsym(handle, kEntrySymbol));
  const Functions* f = entry ? entry() : nullptr;
  if (!f || f->abi_version != kAbiVersion || !f->write || !f->read)
    throw std::runtime_error(fmt::format(
        "image I/O: {} is not an image module of this vrv build (rebuild vrv)", path.string()));
  return f;  // never unloaded: OpenImageIO keeps threads and static state
}

}  // namespace

const Functions& functions() {
  static std::mutex mutex;
  static const Functions* loaded = nullptr;
  std::lock_guard lock(mutex);
  if (!loaded) loaded = load();  // a failed load throws and is retried by the next call
  return *loaded;
}

BackgroundLoad::BackgroundLoad() {
  locate();
  load_ = std::async(std::launch::async, [] { functions(); });
}

BackgroundLoad::~BackgroundLoad() {
  if (load_.valid()) load_.wait();  // an error here was the caller's to take from wait()
}

void BackgroundLoad::wait() {
  if (load_.valid()) load_.get();
}

ReadResult read_file(const std::filesystem::path& path, const ReadRequest& request) {
  auto fail = [&](std::string reason) {
    std::replace_if(reason.begin(), reason.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
    return std::runtime_error(fmt::format("{}: {}", path.string(), reason));
  };
  std::error_code ec;
  if (!fs::exists(path, ec)) throw fail("cannot read: no such file");
  if (fs::is_directory(path, ec)) throw fail("cannot read: is a directory");
  // Before libpng or OpenEXR can allocate what a damaged header claims (lib/io/image_structure.h).
  if (const std::string damaged = image_file_structure_problem(path); !damaged.empty()) throw fail(damaged);
  ReadResult result;
  const std::string why = functions().read(path.string(), request, result);
  if (!why.empty()) throw fail(why);
  return result;
}

}  // namespace vrv::image_module

// Sanitized builds (VRV_SANITIZE, VRV_FUZZ): OpenImageIO's PNG reader leaks the error message of a
// damaged PNG (31 bytes a read: a string made in ImageInput::geterror whose destructor libpng's
// longjmp skips, inside OpenImageIO 2.4 and libpng; nothing vrv frees or can free).  LeakSanitizer
// reads this default suppression in every sanitized process (CTest, .ci/run, the fuzzers, a shell),
// where a suppression file would need LSAN_OPTIONS set each time; it matches only leaks allocated
// under that one function.
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define VRV_LSAN_SUPPRESSIONS 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define VRV_LSAN_SUPPRESSIONS 1
#endif
#ifdef VRV_LSAN_SUPPRESSIONS
extern "C" __attribute__((visibility("default"), used)) const char* __lsan_default_suppressions() {
  // Teem 1.12 (Debian's libteem, the NRRD reader) leaks its gzip state and an airArray when it
  // refuses damaged gzip data or a malformed magic line (tests/fuzz/nrrd_reader_fuzz.cpp); GCC's
  // fast unwinder stops inside zlib there, so zlib's own frames are named too.
  return "leak:OpenImageIO_v2_4::ImageInput::geterror\n"
         "leak:_nrrdGzOpen\nleak:airArrayNew\nleak:airArrayLenSet\nleak:libteem.so\nleak:libz.so.1\n";
}
// Without this LeakSanitizer lists the suppressions it used on stderr at exit, lines after vrv's one.
extern "C" __attribute__((visibility("default"), used)) const char* __lsan_default_options() {
  return "print_suppressions=0";
}
#endif
