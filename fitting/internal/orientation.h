// Internal to tpcal::fitting: the documented sign rules for normals, axes and directions.
#pragma once

#include <Eigen/Core>
#include <optional>

namespace tpcal::fitting::internal {

// The default sign of an unsigned direction: +z component positive; if it is exactly 0,
// +y; then +x. (Deterministic, not rotation-equivariant: pass a hint where it matters.)
inline Eigen::Vector3d OrientByAxesRule(const Eigen::Vector3d& d) {
  const double key = d.z() != 0.0 ? d.z() : (d.y() != 0.0 ? d.y() : d.x());
  return key < 0.0 ? Eigen::Vector3d(-d) : d;
}

// Along `hint` if given and not perpendicular, else OrientByAxesRule.
inline Eigen::Vector3d OrientAlong(const Eigen::Vector3d& d, const std::optional<Eigen::Vector3d>& hint) {
  if (hint.has_value()) {
    const double dot = d.dot(*hint);
    if (dot > 0.0) return d;
    if (dot < 0.0) return -d;
  }
  return OrientByAxesRule(d);
}

}  // namespace tpcal::fitting::internal
