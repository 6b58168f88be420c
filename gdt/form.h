// Form characteristics about least-squares features (ISO 1101 roundness, flatness,
// straightness evaluated with the Gaussian reference of ISO 12181/12781/12780), and the
// circularity profile dr(theta) of seed 002 section 2.2 (Table 1 items a-d). Minimum-zone
// values come from gdt/form_zone.h. Lengths in mm, angles in rad.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <span>
#include <vector>

#include "fitting/features.h"

namespace tpcal::gdt {

// One point of a circularity profile. theta_rad in [0, 2 pi): angle of the point about the
// circle centre, counter-clockwise from the +u axis of the plane (datum +X for datum_xy) about
// the plane normal (datum +Z). dr_mm = |p - c| - r: positive outside the LS circle (away from
// its centre). index: position of the point in the input span.
struct RadialDeviation {
  double theta_rad = 0;
  double dr_mm = 0;
  std::size_t index = 0;
};

// Radial deviations of in-plane points about `circle`, sorted by theta (ties by index).
std::vector<RadialDeviation> CircularityProfile(std::span<const Eigen::Vector2d> points_mm,
                                                const fitting::Circle2& circle);

// max dr - min dr of a profile (0 for an empty one): LS roundness.
double ProfileRange(std::span<const RadialDeviation> profile);

// LS flatness: max - min signed distance of the points from `plane`.
double LsFlatness(std::span<const Eigen::Vector3d> points_mm, const fitting::Plane& plane);

// LS straightness of a line in a plane: max - min signed distance from `line`.
double LsStraightness2(std::span<const Eigen::Vector2d> points_mm, const fitting::Line2& line);

// LS straightness of a line in space: diameter of the cylinder about `line` that encloses the
// points (2 x the largest distance), the ISO 1101 zone for a tolerance marked with a diameter.
double LsStraightness3(std::span<const Eigen::Vector3d> points_mm, const fitting::Line3& line);

}  // namespace tpcal::gdt
