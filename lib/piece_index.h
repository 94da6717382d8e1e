#pragma once
// The pieces a memo keeps for the current panel (lib/spectral_depth.h, lib/shading_memo.h), found
// by their ends in expected constant time.  The memos scanned every kept piece on a miss, and the
// first channel of a walk misses on every piece it reaches: those scans were a third of a shaded
// RGB Marschner-Lobb ray's time (perf record: SpectralDepthShare's find and ShadingMemo::read),
// more than the S they saved.  Open addressing over a power-of-two table at least twice the pieces
// kept; a new panel clears it by a generation count (a grid ray's one-piece panels pay nothing per
// panel), and the table is made on first use (a memo that is off costs nothing).
#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace vrv::detail {

class PieceIndex {
 public:
  // At most `most` entries between clears.
  explicit PieceIndex(std::size_t most) : size_(std::bit_ceil(2 * most)) {}

  void clear() {
    if (++generation_ != 0) return;
    for (Slot& s : slots_) s.generation = 0;  // wrapped: stale slots would look current
    generation_ = 1;
  }
  // Entry `entry` holds the piece [c, d] (several entries may hold one piece).
  void add(double c, double d, std::uint32_t entry) {
    if (slots_.empty()) slots_.resize(size_);
    std::size_t i = home(c, d);
    while (slots_[i].generation == generation_) i = (i + 1) & (size_ - 1);
    slots_[i] = {generation_, entry, c, d};
  }
  // f(entry) for each entry holding [c, d], in the order added, until f returns true; whether one did.
  // A piece whose ends compare equal but differ in bits (0 and -0) is a miss: the memo computes it.
  template <class F>
  bool find(double c, double d, F&& f) const {
    if (slots_.empty()) return false;
    for (std::size_t i = home(c, d); slots_[i].generation == generation_; i = (i + 1) & (size_ - 1))
      if (slots_[i].c == c && slots_[i].d == d && f(slots_[i].entry)) return true;
    return false;
  }
  // Where probing for [c, d] starts (exposed for tests): splitmix64's finaliser over both ends, so
  // every bit reaches the low bits the mask keeps.  A multiplication alone left them to the ends'
  // low mantissa bits, which are 0 for dyadic ends: the pieces [i/64, (i+1)/64] all took one slot
  // and every lookup was a scan again (PieceIndex.DyadicPiecesSpreadAsRandomOnesDo).
  std::size_t home(double c, double d) const {
    std::uint64_t h = std::bit_cast<std::uint64_t>(c) ^ std::rotl(std::bit_cast<std::uint64_t>(d), 32);
    h ^= h >> 30;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 27;
    h *= 0x94D049BB133111EBull;
    h ^= h >> 31;
    return static_cast<std::size_t>(h) & (size_ - 1);
  }

 private:
  struct Slot {
    std::uint32_t generation = 0;
    std::uint32_t entry = 0;
    double c = 0, d = 0;
  };
  std::size_t size_;
  std::vector<Slot> slots_;
  std::uint32_t generation_ = 1;
};

}  // namespace vrv::detail
