#pragma once
// The one spelling of "no value" in fits, tables and statistics: NaN, written "nan" by the tables.
#include <limits>

namespace vrv {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace vrv
