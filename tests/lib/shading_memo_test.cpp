// detail::ShadingMemo (lib/shading_memo.h): S kept for the other channels of a walk.
#include "lib/shading_memo.h"

#include <gtest/gtest.h>

#include <array>
#include <span>
#include <vector>

namespace vrv::shading_memo_test {
namespace {

using detail::ShadingMemo;

TEST(ShadingMemo, ReadsWhatWasKeptForTheSamePieceAndNodes) {
  ShadingMemo memo(true);
  memo.keep_switches(0, 1, std::vector<WeightSwitch>{{0.25, 1e-9, true, true}});
  const std::array<double, 3> ts{0.5, 0.375, 0.25}, s{0.9, 0.8, 0.7}, noise{1e-16, 2e-16, 3e-16};
  memo.keep(0.25, 0.5, ts, s, noise);
  std::array<double, 3> s2{}, noise2{};
  ASSERT_TRUE(memo.read(0.25, 0.5, ts, s2, noise2));
  EXPECT_EQ(s2, s);
  EXPECT_EQ(noise2, noise);
  std::vector<WeightSwitch> out{{0.9, 0, false, true}};
  ASSERT_TRUE(memo.read_switches(0, 1, out));
  ASSERT_EQ(out.size(), 2u);  // appended
  EXPECT_EQ(out[1].t, 0.25);
  EXPECT_TRUE(out[1].jump);
}

// A memo holding the panel (0, 1) and its piece [0.25, 0.5] at two nodes.
constexpr std::array<double, 2> kNodes{0.5, 0.25}, kS{0.9, 0.7}, kNoise{0, 0};
ShadingMemo with_one_piece(bool on) {
  ShadingMemo memo(on);
  memo.keep_switches(0, 1, {});
  memo.keep(0.25, 0.5, kNodes, kS, kNoise);
  return memo;
}
bool reads(ShadingMemo& memo, double c, double d, std::span<const double> ts) {
  std::array<double, 4> s{}, noise{};
  return memo.read(c, d, ts, std::span(s).first(ts.size()), std::span(noise).first(ts.size()));
}
bool reads_switches(const ShadingMemo& memo, double a, double b) {
  std::vector<WeightSwitch> switches;
  return memo.read_switches(a, b, switches);
}

TEST(ShadingMemo, AnotherPieceOrOtherNodesAreNotRead) {
  ShadingMemo memo = with_one_piece(true);
  EXPECT_TRUE(reads(memo, 0.25, 0.5, kNodes));
  EXPECT_FALSE(reads(memo, 0.25, 0.75, kNodes));
  EXPECT_FALSE(reads(memo, 0.0, 0.5, kNodes));
  EXPECT_FALSE(reads(memo, 0.25, 0.5, std::array<double, 2>{0.5, 0.3}));
  EXPECT_FALSE(reads(memo, 0.25, 0.5, std::array<double, 3>{0.5, 0.375, 0.25}));
  EXPECT_FALSE(reads_switches(memo, 0, 2));
}

TEST(ShadingMemo, ANewPanelForgetsTheLastOnesPieces) {
  ShadingMemo memo = with_one_piece(true);
  memo.keep_switches(1, 2, {});
  EXPECT_FALSE(reads(memo, 0.25, 0.5, kNodes));
  EXPECT_FALSE(reads_switches(memo, 0, 1));
  EXPECT_TRUE(reads_switches(memo, 1, 2));
}

TEST(ShadingMemo, OffKeepsNothing) {
  ShadingMemo memo = with_one_piece(false);
  EXPECT_FALSE(reads(memo, 0.25, 0.5, kNodes));
  EXPECT_FALSE(reads_switches(memo, 0, 1));
}

// Pieces are asked for in the order they were kept, from where the last lookup ended; any order
// still finds them, and past kMaxPieces nothing more is kept.
TEST(ShadingMemo, FindsPiecesInAnyOrderAndKeepsAtMostItsCap) {
  ShadingMemo memo(true);
  memo.keep_switches(0, 1, {});
  const auto piece = [](std::size_t k) { return std::array<double, 1>{static_cast<double>(k)}; };
  for (std::size_t k = 0; k < ShadingMemo::kMaxPieces + 5; ++k) memo.keep(k, k + 1, piece(k), piece(k), piece(k));
  std::array<double, 1> s{}, noise{};
  for (std::size_t k : {std::size_t{7}, std::size_t{3}, ShadingMemo::kMaxPieces - 1, std::size_t{0}}) {
    ASSERT_TRUE(memo.read(k, k + 1, piece(k), s, noise)) << k;
    EXPECT_EQ(s[0], static_cast<double>(k));
  }
  EXPECT_FALSE(memo.read(ShadingMemo::kMaxPieces, ShadingMemo::kMaxPieces + 1, piece(ShadingMemo::kMaxPieces), s, noise));
}

}  // namespace
}  // namespace vrv::shading_memo_test
