#include "kinematics/inverse_kinematics.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "core/units.h"
#include "kinematics/forward_kinematics.h"

namespace tpcal::kinematics {

Result<AxisState> NominalAxesForToolPoint(const MachineModel& model,
                                          const Eigen::Vector3d& point_in_part_mm,
                                          const AxisState& rotary,
                                          const Eigen::Vector3d& contact_in_tool_mm,
                                          const InverseKinematicsOptions& options) {
  if (!point_in_part_mm.allFinite() || !contact_in_tool_mm.allFinite()) {
    return Status(StatusCode::kInvalidArgument, "inverse kinematics: non-finite target");
  }
  AxisState s = rotary;
  s.x_mm = s.y_mm = s.z_mm = 0.0;
  const Eigen::Vector3d p0 = NominalToolPointInPart(model, s, contact_in_tool_mm);
  // The nominal chain is affine in X, Y, Z for fixed rotary axes: p = p0 + M [x y z].
  Eigen::Matrix3d M;
  for (int i = 0; i < 3; ++i) {
    AxisState si = s;
    SetPosition(&si, AxisFromIndex(i), 1.0);
    M.col(i) = NominalToolPointInPart(model, si, contact_in_tool_mm) - p0;
  }
  Eigen::FullPivLU<Eigen::Matrix3d> lu(M);
  if (lu.rank() < 3) {
    return Status(StatusCode::kDegenerate, "inverse kinematics: linear axes do not span space");
  }
  const Eigen::Vector3d xyz = lu.solve(point_in_part_mm - p0);
  s.x_mm = xyz.x();
  s.y_mm = xyz.y();
  s.z_mm = xyz.z();
  if (options.check_strokes) {
    TPCAL_RETURN_IF_ERROR(CheckStrokes(model, s).WithContext("inverse kinematics"));
  }
  return s;
}

namespace {

double WrapPi(double a) {
  a = std::remainder(a, 2.0 * kPi);
  return a;
}

}  // namespace

Result<std::vector<AxisState>> RotaryAnglesForToolAxis(const MachineModel& model,
                                                       const Eigen::Vector3d& tool_axis_in_part,
                                                       double c_hint_rad,
                                                       const InverseKinematicsOptions& options) {
  const double norm = tool_axis_in_part.norm();
  if (!(std::abs(norm - 1.0) < 1e-9)) {
    return Status(StatusCode::kInvalidArgument, "tool axis direction must be a unit vector");
  }
  const Eigen::Vector3d d = tool_axis_in_part;
  std::vector<AxisState> candidates;
  constexpr double kTiny = 1e-12;
  if (model.type == MachineType::kXyz) {
    if ((d - Eigen::Vector3d::UnitZ()).norm() > 1e-9) {
      return Status(StatusCode::kInvalidArgument, "a 3-axis machine can only hold the tool along +Z");
    }
    candidates.push_back(AxisState{});
  } else {
    // ac_table: d = (sin A sin C, -sin A cos C, cos A); bc_table and bhead_ctable:
    // d = (sin B cos C, sin B sin C, cos B) (checked against the forward chain below).
    const double tilt = std::acos(std::clamp(d.z(), -1.0, 1.0));
    for (double sign : {1.0, -1.0}) {
      const double t = sign * tilt;
      const double st = std::sin(t);
      double c = c_hint_rad;
      if (std::abs(st) > kTiny) {
        c = model.type == MachineType::kAcTable ? std::atan2(d.x() / st, -d.y() / st)
                                                : std::atan2(d.y() / st, d.x() / st);
      }
      AxisState s;
      if (model.type == MachineType::kAcTable) {
        s.a_rad = t;
      } else {
        s.b_rad = t;
      }
      s.c_rad = std::abs(st) > kTiny ? WrapPi(c) : c;
      candidates.push_back(s);
      if (std::abs(st) <= kTiny) break;  // one solution at zero (or 180 deg) tilt
    }
  }
  std::vector<AxisState> out;
  std::string why;
  for (const AxisState& s : candidates) {
    if ((NominalToolAxisInPart(model, s) - d).norm() > 1e-9) {
      return Status(StatusCode::kInternal, "rotary inverse kinematics disagrees with the chain");
    }
    if (options.check_strokes) {
      // Only the rotary strokes matter here; linear axes are solved separately.
      bool ok = true;
      for (const AxisLink& l : model.links) {
        if (!IsRotary(l.axis) || l.continuous) continue;
        const double q = Position(s, l.axis);
        if (q < l.min_position || q > l.max_position) {
          ok = false;
          why = std::string("axis ") + AxisLetter(l.axis) + " outside its stroke";
        }
      }
      if (!ok) continue;
    }
    out.push_back(s);
  }
  if (out.empty()) {
    return Status(StatusCode::kInvalidArgument, "no rotary position reaches the tool axis: " + why);
  }
  return out;
}

}  // namespace tpcal::kinematics
