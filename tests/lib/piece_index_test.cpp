#include "lib/piece_index.h"

#include <cstdint>
#include <set>
#include <vector>

#include <gtest/gtest.h>

namespace vrv::detail {
namespace {

std::vector<std::uint32_t> entries_of(const PieceIndex& index, double c, double d) {
  std::vector<std::uint32_t> out;
  index.find(c, d, [&](std::uint32_t e) {
    out.push_back(e);
    return false;  // every one
  });
  return out;
}

// Every entry of a piece, in the order added, and no other piece's, with the table as full as a
// memo fills it (its cap of pieces), and nothing after a clear.
TEST(PieceIndex, FindsEveryEntryOfAPieceInOrderAndNothingAfterAClear) {
  constexpr std::size_t kMost = 64;
  PieceIndex index(kMost);
  EXPECT_TRUE(entries_of(index, 0, 1).empty());  // nothing made yet
  for (std::uint32_t e = 0; e < kMost; ++e) index.add(0.25 * (e % 16), 0.25 * (e % 16) + 1, e);
  for (std::uint32_t k = 0; k < 16; ++k)
    EXPECT_EQ(entries_of(index, 0.25 * k, 0.25 * k + 1), (std::vector<std::uint32_t>{k, k + 16, k + 32, k + 48})) << k;
  EXPECT_TRUE(entries_of(index, 0.25, 1.0).empty());
  EXPECT_TRUE(entries_of(index, 0, 1.25).empty());
  // find stops where f says so.
  int asked = 0;
  EXPECT_TRUE(index.find(0.5, 1.5, [&](std::uint32_t e) { return ++asked, e == 18; }));
  EXPECT_EQ(asked, 2);
  index.clear();
  EXPECT_TRUE(entries_of(index, 0, 1).empty());
  index.add(0, 1, 7);
  EXPECT_EQ(entries_of(index, 0, 1), (std::vector<std::uint32_t>{7}));
}

// Pieces with dyadic ends (a bisected unit stretch) take as many distinct slots as random keys
// would (64 into 128: about 128 (1 - e^-1/2) = 50); a hash of the ends' low mantissa bits put
// every one of them in one slot, and each lookup scanned the panel's pieces as before the index.
TEST(PieceIndex, DyadicPiecesSpreadAsRandomOnesDo) {
  const PieceIndex index(64);
  std::set<std::size_t> slots;
  for (int i = 0; i < 64; ++i) slots.insert(index.home(i / 64.0, (i + 1) / 64.0));
  EXPECT_GE(slots.size(), 40u);
  slots.clear();
  for (int i = 0; i < 64; ++i) slots.insert(index.home(-1 + i / 32.0, -1 + (i + 1) / 32.0));
  EXPECT_GE(slots.size(), 40u);
}

}  // namespace
}  // namespace vrv::detail
