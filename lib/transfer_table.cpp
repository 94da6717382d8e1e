#include "lib/transfer_table.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "lib/option_error.h"
#include "lib/util/enum_names.h"

namespace vrv {
namespace {

constexpr NameTable<TableLookup, 2> kTableLookupNames{{{TableLookup::centred, "centred"}, {TableLookup::uncentred, "uncentred"}}};
static_assert(names_complete(kTableLookupNames));

}  // namespace

std::optional<TableLookup> parse_table_lookup(std::string_view name) { return parse_name(kTableLookupNames, name); }
std::string table_lookup_list() { return name_list(kTableLookupNames); }
std::string_view table_lookup_name(TableLookup t) { return name_of(kTableLookupNames, t); }

TransferTable::TransferTable(const PiecewiseLinear& curve, double lo, double hi, int n, TableLookup lookup)
    : lo_(lo) {
  if (n < 2 || n > kMaxTableSize)
    throw OptionError(Option::table_size, fmt::format("must be in [2, {}], got {}", kMaxTableSize, n));
  if (!std::isfinite(lo) || !std::isfinite(hi) || hi < lo)
    throw OptionError(Option::table_size, fmt::format("bad value range [{}, {}]", lo, hi));
  entries_.resize(n);
  for (int i = 0; i < n; ++i) entries_[i] = curve(i == n - 1 ? hi : lo + (hi - lo) * i / (n - 1));
  const double width = hi - lo;
  if (width == 0) {
    scale_ = shift_ = 0;  // every value reads entry 0 (= all entries)
  } else if (lookup == TableLookup::centred) {
    scale_ = (n - 1) / width;
    shift_ = 0;
  } else {
    scale_ = n / width;
    shift_ = 0.5;
  }
}

double TransferTable::operator()(double v) const {
  const double last = static_cast<double>(entries_.size() - 1);
  const double x = std::clamp((v - lo_) * scale_ - shift_, 0.0, last);  // NaN v -> NaN x: see below
  if (std::isnan(x)) return std::numeric_limits<double>::quiet_NaN();
  const auto i = std::min(static_cast<std::size_t>(x), entries_.size() - 2);
  const double f = x - static_cast<double>(i);
  return entries_[i] + f * (entries_[i + 1] - entries_[i]);
}

}  // namespace vrv
