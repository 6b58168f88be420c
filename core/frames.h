// Rigid frames. A transform is named target_from_source and maps coordinates of a point
// expressed in `source` into `target`: p_in_part = part_from_cmm * p_in_cmm.
// Eigen::Isometry3d holds rotation and translation (mm); compose right to left.
#pragma once

#include <Eigen/Geometry>

namespace tpcal {

using Rigid3 = Eigen::Isometry3d;

// Rotation matrix of `angle_rad` about unit axis x, y or z (right-hand rule, ISO 841).
Eigen::Matrix3d RotX(double angle_rad);
Eigen::Matrix3d RotY(double angle_rad);
Eigen::Matrix3d RotZ(double angle_rad);

// Rigid transform from rotation and translation (mm).
Rigid3 MakeRigid(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation_mm);

// Small-angle rigid transform: rotation exp([w]x) with w = (rx, ry, rz) rad, then translation.
Rigid3 RigidFromTwist(const Eigen::Vector3d& rotation_rad, const Eigen::Vector3d& translation_mm);

// Any unit vector perpendicular to unit `v` (deterministic choice).
Eigen::Vector3d AnyPerpendicular(const Eigen::Vector3d& v);

}  // namespace tpcal
