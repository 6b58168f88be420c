// Location characteristics (ISO 1101 concentricity, position; distance between planes), in
// the datum frame. Lengths in mm.
//
// SIGN CONVENTIONS (tested in location_test.cc and inspection_test.cc):
//  - Concentricity of feature F to datum D in plane P (datum_xy by default):
//      (du, dv) = centre(F) - centre(D), both centres projected into P; for datum_xy that is
//      (dx, dy) in datum X and Y. Seed 002 Table 1: dx_{S4,SR} = x(S4) - x(S_R).
//      ISO 1101 zone diameter = 2 * sqrt(du^2 + dv^2).
//  - Position of a centre versus its nominal: (du, dv) = measured - nominal, ISO 1101 position
//      diameter = 2 * |(du, dv)| (3D: spherical zone 2 * |(dx, dy, dz)|).
//  - Distance of plane F from datum plane D: d = n_D . (c_F - p_D), with n_D the datum's
//      oriented normal (+Z of the turning frame for B_R), c_F the foot on F's LS plane of F's
//      point centroid, p_D a point of D's LS plane. error = d - nominal: positive when F sits
//      further along +n_D than nominal. separation_error = |d| - |nominal|: positive when the
//      planes are further apart than nominal, whichever side F is on (valid while d and nominal
//      have the same sign). Seed 002 #3: B3 lies below B_R (nominal d = -30 mm for the piece of
//      testpieces/README.md), so error = -separation_error; the paper's dd_{B3,BR} (eq. 14, the
//      change of z(B_R) - z(B3)) is separation_error.
#pragma once

#include <Eigen/Core>

#include "fitting/features.h"
#include "gdt/plan.h"

namespace tpcal::gdt {

// In-plane coordinates (u, v) of a datum-frame point for a projection plane:
// datum_xy -> (x, y), datum_yz -> (y, z), datum_zx -> (z, x). kNone is a programmer error
// (asserted) and returns (x, y).
Eigen::Vector2d InPlane(const Eigen::Vector3d& p_datum_mm, Projection plane);
// The coordinate along the projection plane's normal: z, x or y.
double AlongNormal(const Eigen::Vector3d& p_datum_mm, Projection plane);
// Datum-frame point from in-plane coordinates and the coordinate along the plane normal.
Eigen::Vector3d FromPlane(const Eigen::Vector2d& uv_mm, double normal_mm, Projection plane);
// The unit normal of the projection plane in the datum frame (+Z, +X or +Y).
Eigen::Vector3d PlaneNormal(Projection plane);
// Value-name letters of the in-plane axes: {"x","y"}, {"y","z"}, {"z","x"}.
std::pair<const char*, const char*> AxisLetters(Projection plane);

struct PlanarOffset {
  Eigen::Vector2d delta_mm = Eigen::Vector2d::Zero();  // (du, dv)
  double zone_diameter_mm = 0;                         // 2 |delta|
};

// Feature centre minus datum centre (or minus nominal), in-plane coordinates.
PlanarOffset CenterOffset(const Eigen::Vector2d& center_mm, const Eigen::Vector2d& reference_mm);

struct PlaneDistanceResult {
  double distance_mm = 0;  // signed, along the datum normal
  double error_mm = 0;     // distance - nominal
  double separation_error_mm = 0;  // |distance| - |nominal|
};

// Distance of `feature` (its point_mm is taken as c_F) from `datum` (its normal oriented).
PlaneDistanceResult PlaneDistance(const fitting::Plane& feature, const fitting::Plane& datum, double nominal_mm);

}  // namespace tpcal::gdt
