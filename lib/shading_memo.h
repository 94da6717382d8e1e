#pragma once
// S along one ray, kept for the channels of an RGB walk (lib/reference_channels.h).  Every channel
// weighs its emission with the same S at the same pieces' nodes and cuts each panel at the same
// switches, so the first channel to ask computes them and the others read them: bitwise what they
// would compute (S, with its gradients and powers, was most of a shaded RGB ray's time; channels
// that cut a piece alike share it).  Holds the current panel's switches and the values of up to
// kMaxPieces of its pieces; a new panel clears it.  Off where one channel emits (grey, or grey
// and alpha), which asks for each once.
#include <cstddef>
#include <span>
#include <vector>

#include "lib/piece_index.h"
#include "lib/weight_switch.h"

namespace vrv::detail {

class ShadingMemo {
 public:
  static constexpr std::size_t kMaxPieces = 256;
  explicit ShadingMemo(bool on) : on_(on) {}

  // The switches in (a, b) appended to `out`, when they are kept.
  bool read_switches(double a, double b, std::vector<WeightSwitch>& out) const;
  // The switches of a new panel (a, b): what the memo held before is another panel's.
  void keep_switches(double a, double b, std::span<const WeightSwitch> switches);
  // S and its rounding at ts of the piece [c, d], when they are kept.
  bool read(double c, double d, std::span<const double> ts, std::span<double> s, std::span<double> noise);
  void keep(double c, double d, std::span<const double> ts, std::span<const double> s,
            std::span<const double> noise);

 private:
  struct Piece {
    double c = 0, d = 0;
    std::size_t offset = 0, count = 0;  // ts, s and noise at data_[offset ...], count each
  };
  bool matches(const Piece& p, double c, double d, std::span<const double> ts) const;

  bool on_;
  bool has_panel_ = false;
  double a_ = 0, b_ = 0;
  std::vector<WeightSwitch> switches_;
  std::vector<Piece> pieces_;
  std::vector<double> data_;
  PieceIndex index_{kMaxPieces};  // where each kept piece is
};

}  // namespace vrv::detail
