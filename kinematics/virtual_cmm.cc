#include "kinematics/virtual_cmm.h"

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "core/portable_random.h"
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
  const double u1 = UniformUnit(rng);
  const double u2 = UniformUnit(rng);
  const double u3 = UniformUnit(rng);
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
    const double max_mm = options.max_translation_mm;
    Eigen::Matrix3d R;
    if (options.any_orientation) {
      R = RandomRotation(rng);
    } else {
      R = Eigen::AngleAxisd(UniformIn(rng, -kPi, kPi), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    }
    Eigen::Vector3d t;  // drawn x, y, z in this order (argument order is unspecified in C++)
    for (int k = 0; k < 3; ++k) t(k) = UniformIn(rng, -max_mm, max_mm);
    out.cmm_from_part = MakeRigid(R, t);
  }
  out.points = actual_in_part;
  out.points.source = actual_in_part.source + " (virtual CMM)";
  const double probe_mm = UmToMm(options.probe_radius_error_um);
  const double sigma_mm = UmToMm(options.noise_sigma_um);
  for (size_t i = 0; i < actual_in_part.size(); ++i) {
    const Eigen::Vector3d& n = actual_in_part.normal[i];
    if (!(std::abs(n.norm() - 1.0) < 1e-6)) {
      return Status(StatusCode::kInvalidArgument,
                    "virtual CMM: normal of point " + std::to_string(i) + " is not a unit vector");
    }
    const double shift = probe_mm + sigma_mm * StandardNormal(rng);
    out.points.xyz_mm[i] = out.cmm_from_part * (actual_in_part.xyz_mm[i] + shift * n);
    out.points.normal[i] = out.cmm_from_part.linear() * n;
  }
  return out;
}

}  // namespace tpcal::kinematics
