#include "gdt/location.h"

#include <cassert>
#include <cmath>

namespace tpcal::gdt {

Eigen::Vector2d InPlane(const Eigen::Vector3d& p, Projection plane) {
  switch (plane) {
    case Projection::kDatumYZ: return {p.y(), p.z()};
    case Projection::kDatumZX: return {p.z(), p.x()};
    case Projection::kDatumXY: return {p.x(), p.y()};
    case Projection::kNone: break;
  }
  assert(false && "InPlane needs a projection plane");
  return {p.x(), p.y()};
}

double AlongNormal(const Eigen::Vector3d& p, Projection plane) {
  switch (plane) {
    case Projection::kDatumYZ: return p.x();
    case Projection::kDatumZX: return p.y();
    default: return p.z();
  }
}

Eigen::Vector3d FromPlane(const Eigen::Vector2d& uv, double w, Projection plane) {
  switch (plane) {
    case Projection::kDatumYZ: return {w, uv.x(), uv.y()};
    case Projection::kDatumZX: return {uv.y(), w, uv.x()};
    default: return {uv.x(), uv.y(), w};
  }
}

Eigen::Vector3d PlaneNormal(Projection plane) {
  switch (plane) {
    case Projection::kDatumYZ: return Eigen::Vector3d::UnitX();
    case Projection::kDatumZX: return Eigen::Vector3d::UnitY();
    default: return Eigen::Vector3d::UnitZ();
  }
}

std::pair<const char*, const char*> AxisLetters(Projection plane) {
  switch (plane) {
    case Projection::kDatumYZ: return {"y", "z"};
    case Projection::kDatumZX: return {"z", "x"};
    default: return {"x", "y"};
  }
}

PlanarOffset CenterOffset(const Eigen::Vector2d& center_mm, const Eigen::Vector2d& reference_mm) {
  PlanarOffset r;
  r.delta_mm = center_mm - reference_mm;
  r.zone_diameter_mm = 2.0 * r.delta_mm.norm();
  return r;
}

PlaneDistanceResult PlaneDistance(const fitting::Plane& feature, const fitting::Plane& datum, double nominal_mm) {
  PlaneDistanceResult r;
  r.distance_mm = datum.SignedDistance(feature.point_mm);
  r.error_mm = r.distance_mm - nominal_mm;
  r.separation_error_mm = std::abs(r.distance_mm) - std::abs(nominal_mm);
  return r;
}

}  // namespace tpcal::gdt
