// lib/verify/reference_cache (through verify_images): the reference is cached by content, and a
// damaged entry is recomputed, never used.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "tests/lib/verify/verify_toy.h"

namespace vrv::verify_toy {
namespace {

namespace fs = std::filesystem;

// Options with an empty reference cache in scratch()/NAME, no diagnosis.
VerifyOptions cached_options(const std::string& name) {
  VerifyOptions o = options();
  o.diagnose = false;
  o.cache_dir = scratch() / name;
  fs::remove_all(o.cache_dir);
  o.scene_text = kScene;
  return o;
}

TEST_F(VerifyToy, ReferenceIsCachedByContent) {
  VerifyOptions o = cached_options("cache");
  const auto images = toy_images(scene, toy::Fault::none, "cache");
  const VerifyReport first = verify_images(scene, images, o);
  const VerifyReport second = verify_images(scene, images, o);
  EXPECT_FALSE(first.reference.from_cache);
  EXPECT_TRUE(second.reference.from_cache);
  EXPECT_EQ(first.reference_image, second.reference_image);
  o.reference_tol = 1e-9;  // another key: rendered again
  EXPECT_FALSE(verify_images(scene, images, o).reference.from_cache);
}

// A cache entry whose values were changed with its key intact flipped the verdict (issue 22): it
// carries a CRC-64 now, and one that fails it (or is cut) is recomputed, said on stderr, never used.
TEST_F(VerifyToy, ADamagedCacheEntryIsRecomputedNeverUsed) {
  const VerifyOptions o = cached_options("damaged_cache");
  const auto images = toy_images(scene, toy::Fault::none, "damaged_cache");
  const VerifyReport first = verify_images(scene, images, o);
  const fs::path file = first.reference.cache_file;
  ASSERT_TRUE(fs::is_regular_file(file));
  const auto damage = [&](auto&& edit) {
    std::string bytes = [&] { std::ifstream in(file, std::ios::binary); std::ostringstream s; s << in.rdbuf(); return s.str(); }();
    edit(bytes);
    std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
    testing::internal::CaptureStderr();
    const VerifyReport again = verify_images(scene, images, o);
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_FALSE(again.reference.from_cache);
    EXPECT_EQ(again.reference_image, first.reference_image);
    return err;
  };
  const std::size_t n = first.reference_image.size();
  EXPECT_EQ(damage([&](std::string& b) { b[b.size() - 8 - 3 * 8 * n + 3] ^= 0x10; }),  // a value's bits
            "vrv: the reference cache " + file.string() + " fails its checksum (changed or damaged); recomputing it\n");
  EXPECT_NE(damage([](std::string& b) { b.resize(b.size() - 9); }).find("is not this reference's"), std::string::npos);
  EXPECT_TRUE(verify_images(scene, images, o).reference.from_cache);  // rewritten whole
}

}  // namespace
}  // namespace vrv::verify_toy
