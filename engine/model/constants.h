// Physical constants and unit helpers. CGS throughout (cm, g, s, dyn), radians inside.
#pragma once

#include <numbers>

namespace aeroflock {

inline constexpr double kAirDensity = 1.225e-3;  // rho, g/cm^3
inline constexpr double kGravity = 980.665;      // G, cm/s^2
inline constexpr double kPi = std::numbers::pi;

constexpr double radians(double degrees) { return degrees * (kPi / 180.0); }
constexpr double degrees(double radians) { return radians * (180.0 / kPi); }

}  // namespace aeroflock
