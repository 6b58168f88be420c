// Hole pattern on a pitch circle: the least-squares circle through the hole centres (seed 002
// "pitch circle of holes C_h"), its radius, and each hole's angular and radial position error.
// In-plane coordinates (u, v) of a datum projection plane (datum_xy: X, Y), mm and rad.
//
// SIGN CONVENTION: angle of hole i = atan2(v_i - v_c, u_i - u_c) about the LS pitch centre c,
// counter-clockwise about the plane normal (datum +Z for datum_xy), i.e. right-handed about +Z.
// angle_error = angle - nominal, wrapped to (-pi, pi]: positive when the hole sits
// counter-clockwise of its nominal. radial_error = |p_i - c| - R_LS: positive outward.
#pragma once

#include <Eigen/Core>
#include <span>
#include <vector>

#include "core/status.h"
#include "fitting/features.h"

namespace tpcal::gdt {

struct HolePosition {
  double angle_rad = 0;        // measured, in (-pi, pi]
  double angle_error_rad = 0;  // measured - nominal, wrapped to (-pi, pi]
  double radial_error_mm = 0;  // distance to the pitch centre - pitch radius
};

struct HolePatternResult {
  fitting::Circle2 pitch;            // the LS pitch circle passed in
  std::vector<HolePosition> holes;   // in member order
  double mean_angle_error_rad = 0;   // the pattern's rotation as a whole
};

// Wraps an angle to (-pi, pi].
double WrapAngle(double angle_rad);

// Errors: kInvalidArgument if the sizes of centers and nominal angles differ.
Result<HolePatternResult> EvaluateHolePattern(const fitting::Circle2& pitch, std::span<const Eigen::Vector2d> centers_mm,
                                              std::span<const double> nominal_angles_rad);

}  // namespace tpcal::gdt
