#pragma once
// The optical-depth half of the reference's spectral rule on one piece [c, d] of a panel
// (RayAccumulator::spectral_try): the proxy's values at the rule's n nodes, tau there, the
// piece's depth and its error, and Phi(t) - Phi(c) at the nodes.  The channels of one walk (an
// RGB ray's, alpha) share the extinction, so wherever their cuts agree they integrate the same
// piece to the same depth: the first to ask computes it, the others read it from the share
// (bit for bit the numbers they would compute), and only the emission is done per channel.
#include <array>
#include <cstddef>
#include <vector>

#include "lib/piece_index.h"
#include "lib/transfer_function.h"

namespace vrv::detail {

// Everything the depth half reads: the piece, the rule's size and the extinction's branch.
struct SpectralDepthKey {
  double c = 0, d = 0;
  int n = 0;
  Convention convention = Convention::emission_extinction;
  Line extinction;  // TransferSegment::extinction_line()
  double unit_length = 1;
  double extinction_slope = 0;  // the branch's max |dtau/dv|
  double value_floor = 1;       // the least size of v its rounding is taken at (RayAccumulator)
  bool operator==(const SpectralDepthKey& o) const {
    return c == o.c && d == o.d && n == o.n && convention == o.convention && extinction.v0 == o.extinction.v0 &&
           extinction.y0 == o.extinction.y0 && extinction.slope == o.extinction.slope &&
           unit_length == o.unit_length && extinction_slope == o.extinction_slope && value_floor == o.value_floor;
  }
};

struct SpectralDepth {
  static constexpr int kMaxNodes = 129;
  std::array<double, kMaxNodes> values;  // the proxy at the nodes (from +1 to -1)
  std::array<double, kMaxNodes> tau;
  std::array<double, kMaxNodes> phi;     // (Phi(t_j) - Phi(c)) / half, non-increasing in j (has_phi only)
  bool has_phi = false;
  double v_max = 1, tau_max = 0;
  double position_noise = 0;             // node_position_noise of the piece
  double dphi = 0, depth_error = 0;
  bool converged = false, at_rounding = false;
  // e^-Phi at the nodes for a channel whose depth before the piece is at_depth (the channels
  // that cut alike reach the piece with the same depth, bit for bit); made by the first to ask.
  bool has_attenuation = false;
  double at_depth = 0;
  std::array<double, kMaxNodes> attenuation;
};

// A panel's depth halves, asked for by the channels in turn; cleared for every panel.  At most
// kMaxPieces are kept (a panel split to the work cap has thousands of tries; past the cap each
// channel computes its own), found by their ends (PieceIndex).
class SpectralDepthShare {
 public:
  static constexpr std::size_t kMaxPieces = 64;
  // The piece's depth half, or nullptr; `with_phi` asks for one that has Phi at the nodes.
  SpectralDepth* find(const SpectralDepthKey& key, bool with_phi) {
    SpectralDepth* found = nullptr;
    index_.find(key.c, key.d, [&](std::uint32_t i) {
      if (!(keys_[i] == key) || !(entries_[i].has_phi || !with_phi)) return false;
      found = &entries_[i];
      return true;
    });
    return found;
  }
  // Room for the piece's depth half (storage kept across panels: no allocation per piece), or
  // nullptr when kMaxPieces are kept.  Valid until the next slot().
  SpectralDepth* slot(const SpectralDepthKey& key) {
    if (used_ == kMaxPieces) return nullptr;
    if (used_ == entries_.size()) keys_.emplace_back(), entries_.emplace_back();
    keys_[used_] = key;
    index_.add(key.c, key.d, static_cast<std::uint32_t>(used_));
    return &entries_[used_++];
  }
  void clear() { used_ = 0, index_.clear(); }
  void reserve(std::size_t pieces) { keys_.reserve(pieces), entries_.reserve(pieces); }

 private:
  std::vector<SpectralDepthKey> keys_;
  std::vector<SpectralDepth> entries_;
  std::size_t used_ = 0;
  PieceIndex index_{kMaxPieces};
};

}  // namespace vrv::detail
