#include "lib/shading_memo.h"

#include <algorithm>

namespace vrv::detail {

bool ShadingMemo::read_switches(double a, double b, std::vector<WeightSwitch>& out) const {
  if (!on_ || !has_panel_ || a != a_ || b != b_) return false;
  out.insert(out.end(), switches_.begin(), switches_.end());
  return true;
}

void ShadingMemo::keep_switches(double a, double b, std::span<const WeightSwitch> switches) {
  if (!on_) return;
  has_panel_ = true, a_ = a, b_ = b;
  switches_.assign(switches.begin(), switches.end());
  pieces_.clear(), data_.clear(), index_.clear();
}

bool ShadingMemo::matches(const Piece& p, double c, double d, std::span<const double> ts) const {
  return p.c == c && p.d == d && p.count == ts.size() &&
         std::equal(ts.begin(), ts.end(), data_.begin() + static_cast<std::ptrdiff_t>(p.offset));
}

bool ShadingMemo::read(double c, double d, std::span<const double> ts, std::span<double> s,
                       std::span<double> noise) {
  if (!on_) return false;
  return index_.find(c, d, [&](std::uint32_t i) {
    const Piece& p = pieces_[i];
    if (!matches(p, c, d, ts)) return false;
    const auto at = data_.begin() + static_cast<std::ptrdiff_t>(p.offset + p.count);
    std::copy_n(at, p.count, s.begin());
    std::copy_n(at + static_cast<std::ptrdiff_t>(p.count), p.count, noise.begin());
    return true;
  });
}

void ShadingMemo::keep(double c, double d, std::span<const double> ts, std::span<const double> s,
                       std::span<const double> noise) {
  if (!on_ || !has_panel_ || pieces_.size() == kMaxPieces) return;
  index_.add(c, d, static_cast<std::uint32_t>(pieces_.size()));
  pieces_.push_back({c, d, data_.size(), ts.size()});
  data_.insert(data_.end(), ts.begin(), ts.end());
  data_.insert(data_.end(), s.begin(), s.begin() + static_cast<std::ptrdiff_t>(ts.size()));
  data_.insert(data_.end(), noise.begin(), noise.begin() + static_cast<std::ptrdiff_t>(ts.size()));
}

}  // namespace vrv::detail
