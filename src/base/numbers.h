// Constants that many files use, defined once (a unity build puts several files in one unit).
#pragma once

#include <limits>
#include <numbers>

namespace hb {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
inline constexpr double kU = 0x1p-24;  // the unit roundoff of float (2^-24)

}  // namespace hb
