#pragma once
// Transfer functions as renderers hold them: an N-entry table (a 1D texture) of one curve,
// read with linear interpolation.  The table covers the transfer function's control-point range
// [lo, hi] (first to last breakpoint), entry i = curve(lo + i (hi - lo) / (N - 1)), so the first
// and last entries are the ends of the range.  Two ways to read it:
//
//   centred    x = (v - lo) / (hi - lo) * (N - 1): entry i is read exactly at its own value.  On
//              a GPU this is the half-texel remap u' = (x + 1/2) / N of the texture coordinate.
//   uncentred  x = (v - lo) / (hi - lo) * N - 1/2: the plain texture coordinate u = (v - lo) /
//              (hi - lo) under a GPU's linear filter, whose texel centres sit at (i + 1/2) / N;
//              the curve is read shifted by between +1/2 and -1/2 of an entry across the range
//              (first order in 1/N).
//
// x is clamped to [0, N - 1] (clamp-to-edge), so values outside the range get the end entries,
// as the continuous transfer function is constant beyond its ends.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "lib/transfer_function.h"

namespace vrv {

enum class TableLookup { centred, uncentred };

std::optional<TableLookup> parse_table_lookup(std::string_view name);  // "centred", "uncentred"
std::string table_lookup_list();  // its names in order, "a, b, c": the choices an error offers
std::string_view table_lookup_name(TableLookup t);

inline constexpr int kMaxTableSize = 1 << 20;

class TransferTable {
 public:
  // Throws std::invalid_argument (naming --table-size) unless 2 <= n <= kMaxTableSize and
  // lo <= hi are finite.  lo == hi gives a constant table of curve(lo).
  TransferTable(const PiecewiseLinear& curve, double lo, double hi, int n, TableLookup lookup);
  double operator()(double v) const;
  const std::vector<double>& entries() const { return entries_; }

 private:
  std::vector<double> entries_;
  double lo_, scale_, shift_;  // x = (v - lo) * scale - shift
};

}  // namespace vrv
