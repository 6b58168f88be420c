// Units: inside tpcal every length is mm and every angle rad, in double precision.
// Outside (files, reports, YAML keys) the unit is part of the key name (radius_mm, tilt_urad).
// Convert only at the edges, with these helpers.
#pragma once

#include <numbers>

namespace tpcal {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kUmPerMm = 1000.0;
inline constexpr double kMmPerInch = 25.4;
inline constexpr double kUradPerRad = 1.0e6;

constexpr double DegToRad(double deg) { return deg * kPi / 180.0; }
constexpr double RadToDeg(double rad) { return rad * 180.0 / kPi; }
constexpr double MmToUm(double mm) { return mm * kUmPerMm; }
constexpr double UmToMm(double um) { return um / kUmPerMm; }
constexpr double RadToUrad(double rad) { return rad * kUradPerRad; }
constexpr double UradToRad(double urad) { return urad / kUradPerRad; }

}  // namespace tpcal
