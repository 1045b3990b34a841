#pragma once
// One millimetre and one degree in the SI units the code computes in (metres, radians), so a
// value reads `2 * kMm` on the way in and `x / kMm` on the way out (in mm).

#include <numbers>

namespace blendbench {

inline constexpr double kMm = 1e-3;                      // m
inline constexpr double kDeg = std::numbers::pi / 180;  // rad

}  // namespace blendbench
