// Fuzz target: the reference cache of `vrv verify` and `vrv gate` (lib/verify.h, reference_image
// with VerifyOptions::cache_dir).  Whatever bytes the cache entry holds, the reference returned is
// the computed one, bit for bit: an entry is used only when whole and its CRC-64 matches, else it
// is recomputed (issue 22: a cache whose values were changed flipped the verdict).  Seed: the real
// entry for the harness's 3 x 2 image (VRV_FUZZ_WRITE_SEED=FILE writes it), and damaged copies.
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "lib/scene_file.h"
#include "lib/verify.h"

#include "tests/fuzz/fuzz_limits.h"

namespace fs = std::filesystem;

namespace {

struct Setup {
  vrv::Scene scene = vrv::parse_scene(vrv::default_scene_toml(), "default");
  vrv::VerifyOptions options;
  vrv::Camera camera;
  vrv::ReferenceImage truth;
  fs::path entry;  // the cache file the options lead to

  Setup() {
    options.reference_tol = 1e-8;
    camera = vrv::verify_camera(scene, options, 3, 2);
    truth = vrv::reference_image(scene, camera, options);  // no cache: computed
    options.cache_dir = vrv::fuzz::scratch_root() / ("vrv-fuzz-cache-" + std::to_string(::getpid()));
    options.scene_text = std::string(vrv::default_scene_toml());
    fs::remove_all(options.cache_dir);
    vrv::reference_image(scene, camera, options);  // writes the entry
    for (const auto& e : fs::directory_iterator(options.cache_dir)) entry = e.path();
    if (entry.empty()) std::abort();
    if (const char* seed = std::getenv("VRV_FUZZ_WRITE_SEED")) fs::copy_file(entry, seed, fs::copy_options::overwrite_existing);
  }
};

bool same(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static Setup s;
  std::ofstream(s.entry, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  const vrv::ReferenceImage r = vrv::reference_image(s.scene, s.camera, s.options);
  if (!same(r.pixels, s.truth.pixels) || !same(r.error_estimate, s.truth.error_estimate) ||
      !same(r.optical_depth, s.truth.optical_depth))
    std::abort();
  return 0;
}
