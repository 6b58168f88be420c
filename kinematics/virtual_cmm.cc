#include "kinematics/virtual_cmm.h"

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "core/units.h"

namespace tpcal::kinematics {

Status VirtualCmmOptions::Validate() const {
  if (!(noise_sigma_um >= 0.0) || !std::isfinite(noise_sigma_um)) {
    return Status(StatusCode::kInvalidArgument, "virtual CMM: noise_sigma_um must be >= 0");
  }
  if (!std::isfinite(probe_radius_error_um)) {
    return Status(StatusCode::kInvalidArgument, "virtual CMM: probe_radius_error_um is not finite");
  }
  if (!(max_translation_mm >= 0.0) || !std::isfinite(max_translation_mm)) {
    return Status(StatusCode::kInvalidArgument, "virtual CMM: max_translation_mm must be >= 0");
  }
  return Status::Ok();
}

namespace {

// Uniform random rotation (Shoemake's unit quaternion method).
Eigen::Matrix3d RandomRotation(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const double u1 = uni(rng), u2 = uni(rng), u3 = uni(rng);
  const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
  const Eigen::Quaterniond q(b * std::cos(2 * kPi * u3), a * std::sin(2 * kPi * u2),
                             a * std::cos(2 * kPi * u2), b * std::sin(2 * kPi * u3));
  return q.normalized().toRotationMatrix();
}

}  // namespace

Result<VirtualCmmResult> MeasureWithVirtualCmm(const PointSet& actual_in_part,
                                               const VirtualCmmOptions& options,
                                               std::mt19937_64& rng) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  if (actual_in_part.normal.size() != actual_in_part.size()) {
    return Status(StatusCode::kInvalidArgument,
                  "virtual CMM: every point needs its nominal normal (" + actual_in_part.source + ")");
  }
  VirtualCmmResult out;
  if (options.random_placement) {
    std::uniform_real_distribution<double> uni(-options.max_translation_mm, options.max_translation_mm);
    Eigen::Matrix3d R;
    if (options.any_orientation) {
      R = RandomRotation(rng);
    } else {
      std::uniform_real_distribution<double> ang(-kPi, kPi);
      R = Eigen::AngleAxisd(ang(rng), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    }
    const Eigen::Vector3d t(uni(rng), uni(rng), uni(rng));
    out.cmm_from_part = MakeRigid(R, t);
  }
  out.points = actual_in_part;
  out.points.source = actual_in_part.source + " (virtual CMM)";
  std::normal_distribution<double> noise(0.0, 1.0);
  const double probe_mm = UmToMm(options.probe_radius_error_um);
  const double sigma_mm = UmToMm(options.noise_sigma_um);
  for (size_t i = 0; i < actual_in_part.size(); ++i) {
    const Eigen::Vector3d& n = actual_in_part.normal[i];
    if (!(std::abs(n.norm() - 1.0) < 1e-6)) {
      return Status(StatusCode::kInvalidArgument,
                    "virtual CMM: normal of point " + std::to_string(i) + " is not a unit vector");
    }
    const double shift = probe_mm + sigma_mm * noise(rng);
    out.points.xyz_mm[i] = out.cmm_from_part * (actual_in_part.xyz_mm[i] + shift * n);
    out.points.normal[i] = out.cmm_from_part.linear() * n;
  }
  return out;
}

}  // namespace tpcal::kinematics
