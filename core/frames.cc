#include "core/frames.h"

#include <cmath>

namespace tpcal {

Eigen::Matrix3d RotX(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()).toRotationMatrix(); }
Eigen::Matrix3d RotY(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()).toRotationMatrix(); }
Eigen::Matrix3d RotZ(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix(); }

Rigid3 MakeRigid(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation_mm) {
  Rigid3 t = Rigid3::Identity();
  t.linear() = rotation;
  t.translation() = translation_mm;
  return t;
}

Rigid3 RigidFromTwist(const Eigen::Vector3d& w, const Eigen::Vector3d& translation_mm) {
  const double angle = w.norm();
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  if (angle > 0.0) r = Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
  return MakeRigid(r, translation_mm);
}

Eigen::Vector3d AnyPerpendicular(const Eigen::Vector3d& v) {
  const Eigen::Vector3d a = std::abs(v.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return v.cross(a).normalized();
}

}  // namespace tpcal
