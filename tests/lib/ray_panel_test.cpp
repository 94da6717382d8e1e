// What a panel keeps of its searches (RayPanel::found): crossings asked for level by level, in any
// order and subsets (the channels of an RGB ray, alpha, judging then integrating), are bitwise a
// fresh panel's answer to the same levels; cached bands are level_band's; a refitted panel
// (forget_derived) answers for its new coefficients.
#include "lib/ray_panel.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace vrv::ray_panel_test {
namespace {

RayPanel random_panel(std::mt19937_64& rng, int n) {
  std::uniform_real_distribution<double> u(-1, 1);
  RayPanel panel{0.5, 1.75, std::vector<double>(n), std::vector<double>(n), 0, 0, true};
  const double decay = 0.3 + 0.5 * (u(rng) + 1) / 2;
  for (int k = 0; k < n; ++k) panel.coefficients[k] = (k == 0 ? 0.5 * u(rng) : u(rng)) * std::pow(decay, k);
  return panel;
}

void expect_same(const std::vector<Crossing>& a, const std::vector<Crossing>& b, int trial) {
  ASSERT_EQ(a.size(), b.size()) << trial;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(std::bit_cast<std::uint64_t>(a[i].t), std::bit_cast<std::uint64_t>(b[i].t)) << trial;
    EXPECT_EQ(a[i].level, b[i].level) << trial;
    EXPECT_EQ(std::bit_cast<std::uint64_t>(a[i].slope), std::bit_cast<std::uint64_t>(b[i].slope)) << trial;
  }
}

TEST(RayPanelFound, CachedCrossingsAreAFreshSearchBitwise) {
  std::mt19937_64 rng(51);
  // Three channels' levels sharing the extinction's (0.1, 0.4), and the alpha channel's.
  const std::vector<std::vector<double>> asks{{-0.5, 0.1, 0.3, 0.4}, {0.1, 0.2, 0.4}, {0.1, 0.4, 0.45, 0.9},
                                              {0.1, 0.4}, {-0.5, 0.1, 0.3, 0.4}};
  int crossings = 0;
  for (int trial = 0; trial < 500; ++trial) {
    const RayPanel shared = random_panel(rng, trial % 4 == 0 ? 4 : 33);
    for (const std::vector<double>& levels : asks) {
      std::vector<Crossing> cached, fresh;
      const ValueRange r1 = find_crossings(shared, levels, cached);
      RayPanel copy = shared;  // the same coefficients, nothing searched yet
      copy.forget_derived();
      const ValueRange r2 = find_crossings(copy, levels, fresh);
      expect_same(cached, fresh, trial);
      EXPECT_EQ(r1.min, r2.min);
      EXPECT_EQ(r1.max, r2.max);
      crossings += static_cast<int>(cached.size());
    }
  }
  EXPECT_GT(crossings, 1000);  // the levels are crossed
}

TEST(RayPanelFound, CachedBandsAreLevelBands) {
  std::mt19937_64 rng(52);
  int bands = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const RayPanel panel = random_panel(rng, 33);
    std::vector<double> parts;
    monotone_breaks(panel, parts);
    for (int pass = 0; pass < 2; ++pass)  // the second pass answers from the cache
      for (std::size_t i = 0; i + 1 < parts.size(); ++i)
        for (double level : {0.1, 0.35})
          for (double margin : {1e-12, 1e-3}) {
            const auto cached = part_level_band(panel, i, level, margin);
            const auto direct = level_band(panel, parts[i], parts[i + 1], level, margin);
            ASSERT_EQ(cached.has_value(), direct.has_value()) << trial;
            if (!cached) continue;
            EXPECT_EQ(cached->u, direct->u);
            EXPECT_EQ(cached->w, direct->w);
            bands += pass == 0;
          }
  }
  EXPECT_GT(bands, 100);
}

TEST(RayPanelFound, ARefittedPanelForgetsTheOldSearch) {
  std::mt19937_64 rng(53);
  const std::vector<double> levels{0.1, 0.4};
  for (int trial = 0; trial < 200; ++trial) {
    RayPanel panel = random_panel(rng, 33);
    std::vector<Crossing> before;
    find_crossings(panel, levels, before);
    const RayPanel next = random_panel(rng, 33);
    panel.coefficients = next.coefficients;
    panel.forget_derived();
    std::vector<Crossing> after, fresh;
    find_crossings(panel, levels, after);
    find_crossings(next, levels, fresh);
    expect_same(after, fresh, trial);
  }
}

}  // namespace
}  // namespace vrv::ray_panel_test
