// Minimum-zone (Chebyshev) form values, the ISO 1101 default criterion, for the form
// characteristics and the fitted features' form values. gdt does not implement minimum zone
// itself: every value comes from fitting/minimum_zone.h (exact / certified evaluations owned by
// the fitting layer). This file is the single place gdt calls that API.
// Widths in mm: circularity = radial separation of the two concentric circles; flatness =
// distance of the two parallel planes; straightness in a plane = distance of the two parallel
// lines; straightness in space = diameter of the enclosing cylinder; cylindricity = radial
// separation of the two coaxial cylinders.
// Errors: the fitting call's (kTooFewPoints, kDegenerate, kNotConverged, ...), or kInternal
// "not available" when this build has no fitting/minimum_zone.h.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <span>
#include <string>

#include "core/status.h"
#include "fitting/features.h"

namespace tpcal::gdt {

struct MinimumZoneValue {
  double width_mm = 0;
  // True when the fitting layer certified optimality (global, or local for cylindricity);
  // otherwise width_mm is still the width of a valid enclosing zone (an upper bound).
  bool verified_optimal = false;
  std::string note;  // the certificate's method and message
};

// True when this build evaluates minimum-zone values (fitting/minimum_zone.h present).
bool MinimumZoneAvailable();

Result<MinimumZoneValue> MinimumZoneCircularity(std::span<const Eigen::Vector2d> points_mm);
Result<MinimumZoneValue> MinimumZoneFlatness(std::span<const Eigen::Vector3d> points_mm);
Result<MinimumZoneValue> MinimumZoneStraightness2(std::span<const Eigen::Vector2d> points_mm);
Result<MinimumZoneValue> MinimumZoneStraightness3(std::span<const Eigen::Vector3d> points_mm);
// `start`: the least-squares cylinder (start of the refinement).
Result<MinimumZoneValue> MinimumZoneCylindricity(std::span<const Eigen::Vector3d> points_mm,
                                                 std::optional<fitting::Cylinder> start);

}  // namespace tpcal::gdt
