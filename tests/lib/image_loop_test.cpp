#include "lib/image_loop.h"

#include <atomic>
#include <cmath>
#include <functional>
#include <span>
#include <vector>

#include <gtest/gtest.h>

namespace vrv {
namespace {

// A camera whose pixel count is no multiple of the block, so the last block is short.
Camera small_camera() {
  Camera c;
  c.width = 37;
  c.height = 23;
  return c;
}

// Something of the ray that differs from pixel to pixel and takes a few operations.
double ray_value(const Ray& r) { return std::sin(7 * r.direction[0]) * std::cos(5 * r.direction[1]) + r.origin[2]; }

TEST(ImageLoop, SameBitsForOneAndTwoThreads) {
  const Camera c = small_camera();
  std::vector<double> one, two;
  {
    const ThreadLimit limit(1);
    one = image_loop(c, ray_value);
  }
  {
    const ThreadLimit limit(2);
    ImageLoopHooks hooks;
    hooks.block = 5;  // many blocks, so both threads take some
    two = image_loop(c, {}, ray_value, hooks);
  }
  ASSERT_EQ(one.size(), 37u * 23u);
  EXPECT_EQ(one, two);
}

TEST(ImageLoop, PositionsAreRowMajorPixels) {
  const Camera c = small_camera();
  const std::vector<long> pixel = image_loop(c, [](const Ray&, long i) { return i; });
  const std::vector<Ray> rays = image_loop(c, [](const Ray& r) { return r; });
  for (long i = 0; i < pixel_count(c); ++i) {
    EXPECT_EQ(pixel[i], i);
    const Ray expected = c.ray(static_cast<int>(i % c.width), static_cast<int>(i / c.width));
    EXPECT_EQ(rays[i].origin, expected.origin);
    EXPECT_EQ(rays[i].direction, expected.direction);
  }
}

TEST(ImageLoop, SubsetKeepsItsOwnOrder) {
  const Camera c = small_camera();
  const std::vector<long> subset{500, 3, 850, 0, 3, 41};
  ImageLoopHooks hooks;
  hooks.block = 4;
  const std::vector<long> got = image_loop(c, subset, [](const Ray&, long i) { return i; }, hooks);
  EXPECT_EQ(got, subset);
  const std::vector<double> whole = image_loop(c, ray_value);
  const std::vector<double> part = image_loop(c, subset, ray_value);
  for (std::size_t k = 0; k < subset.size(); ++k) EXPECT_EQ(part[k], whole[subset[k]]);
}

TEST(ImageLoop, ProgressCountsEveryPositionOncePerBlock) {
  const Camera c = small_camera();
  std::atomic<long> done{0}, calls{0};
  ImageLoopHooks hooks;
  hooks.block = 10;
  hooks.progress = [&](long n) {
    done += n;
    ++calls;
  };
  std::atomic<long> puts{0};
  image_loop_into(c, {}, ray_value, [&](long, double) { ++puts; }, hooks);
  EXPECT_EQ(done, 37 * 23);
  EXPECT_EQ(puts, 37 * 23);
  EXPECT_EQ(calls, (37 * 23 + 9) / 10);
}

TEST(ImageLoop, StopEndsTheLoopBetweenBlocks) {
  const Camera c = small_camera();
  const ThreadLimit limit(1);
  std::atomic<long> polls{0}, done{0};
  ImageLoopHooks hooks;
  hooks.block = 37;
  hooks.stop = [&] { return ++polls > 3; };  // three rows, then stop
  hooks.progress = [&](long n) { done += n; };
  EXPECT_THROW(image_loop(c, {}, ray_value, hooks), WorkCancelled);
  EXPECT_EQ(done, 3 * 37);
}

TEST(ImageLoop, RecordsAreEachPositionsAndTheStoreRestoresOrKeepsThem) {
  const Camera c = small_camera();
  ImageLoopHooks hooks;
  hooks.block = 37;  // one row a block
  const auto record = [](const Ray& ray, std::span<double> out) {
    out[0] = ray_value(ray);
    out[1] = 2 * ray_value(ray);
  };
  const std::vector<double> whole = image_loop(c, ray_value);
  const std::vector<double> plain = image_records(c, {}, 2, record, hooks);
  ASSERT_EQ(plain.size(), 2 * whole.size());
  for (std::size_t i = 0; i < whole.size(); ++i) {
    EXPECT_EQ(plain[2 * i], whole[i]) << i;
    EXPECT_EQ(plain[2 * i + 1], 2 * whole[i]) << i;
  }
  std::atomic<long> computed{0}, stored_blocks{0};
  // Even rows "restored" as -row, odd rows computed.
  const BlockStore store = [&](long first, std::span<double> records, const std::function<void()>& compute) {
    EXPECT_EQ(first % 37, 0);
    EXPECT_EQ(records.size(), 2 * 37u);
    ++stored_blocks;
    if ((first / 37) % 2 == 0) {
      for (double& v : records) v = -static_cast<double>(first / 37);
      return;
    }
    compute();
    computed += static_cast<long>(records.size() / 2);
  };
  const std::vector<double> got = image_records(c, {}, 2, record, hooks, store);
  EXPECT_EQ(stored_blocks, 23);
  EXPECT_EQ(computed, 11 * 37);
  for (long i = 0; i < pixel_count(c); ++i) {
    const long row = i / 37;
    EXPECT_EQ(got[2 * i], row % 2 == 0 ? -static_cast<double>(row) : plain[2 * i]) << i;
  }
}

}  // namespace
}  // namespace vrv
