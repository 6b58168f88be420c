// Exact synthetic probing points (ground truth as library code): circles and plane rings placed
// in a part frame, with optional known radial / normal deviations, then moved rigidly to a
// CMM placement. Used by the gdt tests; usable by any layer that needs points with known
// geometry. Lines are numbered as a point file would number them (first data row on line 4,
// after "# tpcal points v1", "# units: mm" and the header row), so errors citing lines can be
// checked. Normals (i, j, k) are filled, pointing out of the material.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <random>
#include <string>

#include "core/frames.h"
#include "core/point_set.h"

namespace tpcal::gdt {

// In-plane reference axes of a circle or ring with unit `axis`: +u = datum X made
// perpendicular to the axis (datum Y if the axis is along X), +v = axis x u. Theta is measured
// from +u toward +v (the convention of gdt/fitted_feature.h CircleCoordinates).
void InPlaneAxes(const Eigen::Vector3d& axis, Eigen::Vector3d* u, Eigen::Vector3d* v);

struct SyntheticCircle {
  Eigen::Vector3d center_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // unit
  double radius_mm = 1.0;
  int n_points = 16;             // evenly spaced over 360 deg
  double start_angle_rad = 0.0;  // theta of the first point
  bool hole = false;             // normals point toward the axis (a bore / hole wall)
  // Radial deviation dr(theta) in mm added to the radius (positive outward); none: exact circle.
  std::function<double(double theta_rad)> dr_mm{};
};

struct SyntheticPlaneRing {
  Eigen::Vector3d center_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit, out of the material
  double radius_mm = 1.0;  // points on a circle of this radius in the plane
  int n_points = 16;
  double start_angle_rad = 0.0;
  // Deviation along the normal dz(theta) in mm; none: exact plane.
  std::function<double(double theta_rad)> dz_mm{};
};

// Appends the points (and normals, lines, label) of one feature to `ps`.
void AppendCircle(PointSet* ps, const std::string& feature, const SyntheticCircle& c);
void AppendPlaneRing(PointSet* ps, const std::string& feature, const SyntheticPlaneRing& r);

// `ps` with every point and normal moved by `target_from_source`.
PointSet Transformed(const PointSet& ps, const Rigid3& target_from_source);

// A random rigid placement: rotation uniform on SO(3), translation uniform in
// [-max_translation_mm, max_translation_mm]^3. Deterministic for a given generator state.
Rigid3 RandomPlacement(std::mt19937_64& rng, double max_translation_mm);

}  // namespace tpcal::gdt
