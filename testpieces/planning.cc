#include <cmath>

#include "core/units.h"
#include "kinematics/forward_kinematics.h"
#include "kinematics/inverse_kinematics.h"
#include "testpieces/internal/planning.h"

namespace tpcal::testpieces::internal {

kinematics::AxisState RotaryOnly(const kinematics::AxisState& s) {
  kinematics::AxisState r = s;
  r.x_mm = r.y_mm = r.z_mm = 0.0;
  return r;
}

Eigen::Matrix3d PartFromToolRotation(const kinematics::MachineModel& machine, const kinematics::AxisState& rotary) {
  return kinematics::NominalPartFromTool(machine, RotaryOnly(rotary)).rotation();
}

Result<kinematics::AxisState> AxesForRefPoint(const kinematics::MachineModel& machine,
                                              const Eigen::Vector3d& ref_point_part_mm,
                                              const kinematics::AxisState& rotary, bool check_strokes) {
  kinematics::InverseKinematicsOptions options;
  options.check_strokes = check_strokes;
  return kinematics::NominalAxesForToolPoint(machine, ref_point_part_mm, RotaryOnly(rotary),
                                             Eigen::Vector3d::Zero(), options);
}

Result<kinematics::AxisDelta> LinearDeltaFor(const kinematics::MachineModel& machine,
                                             const kinematics::AxisState& rotary, const Eigen::Vector3d& dir_part) {
  TPCAL_ASSIGN_OR_RETURN(const RotaryFrame frame, RotaryFrame::At(machine, rotary));
  return frame.DeltaFor(dir_part);
}

Result<kinematics::CutPoint> MakeCutPoint(const kinematics::MachineModel& machine, const Eigen::Vector3d& p0,
                                          const Eigen::Vector3d& n0, const Eigen::Vector3d& ref_point_part_mm,
                                          const kinematics::AxisState& rotary, const kinematics::SweepDirection& du,
                                          const kinematics::SweepDirection& dv) {
  TPCAL_ASSIGN_OR_RETURN(const RotaryFrame frame, RotaryFrame::At(machine, rotary));
  return frame.MakeCut(p0, n0, ref_point_part_mm, du, dv);
}

Result<RotaryFrame> RotaryFrame::At(const kinematics::MachineModel& machine, const kinematics::AxisState& rotary) {
  RotaryFrame f;
  f.rotary_ = RotaryOnly(rotary);
  // The four evaluations differ in one linear axis: the memo computes the rotary links once, and
  // keeps them for the next frame at the same rotary positions (a milled feature's points).
  thread_local kinematics::Workspace ws;
  const Rigid3 part_from_tool = kinematics::NominalPartFromTool(machine, f.rotary_, &ws);
  f.R_ = part_from_tool.rotation();
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  f.ref0_mm_ = part_from_tool * zero;  // what NominalToolPointInPart(machine, rotary, 0) returns
  Eigen::Matrix3d M;
  for (int i = 0; i < 3; ++i) {
    kinematics::AxisState si = f.rotary_;
    kinematics::SetPosition(&si, kinematics::AxisFromIndex(i), 1.0);
    M.col(i) = kinematics::NominalPartFromTool(machine, si, &ws) * zero - f.ref0_mm_;
  }
  f.lu_.compute(M);
  if (f.lu_.rank() < 3) return Status(StatusCode::kDegenerate, "inverse kinematics: linear axes do not span space");
  return f;
}

kinematics::AxisState RotaryFrame::AxesFor(const Eigen::Vector3d& ref_point_part_mm) const {
  kinematics::AxisState s = rotary_;
  const Eigen::Vector3d xyz = lu_.solve(ref_point_part_mm - ref0_mm_);
  s.x_mm = xyz.x();
  s.y_mm = xyz.y();
  s.z_mm = xyz.z();
  return s;
}

kinematics::AxisDelta RotaryFrame::DeltaFor(const Eigen::Vector3d& dir_part) const {
  return Difference(AxesFor(dir_part), AxesFor(Eigen::Vector3d::Zero()), 1.0);
}

kinematics::CutPoint RotaryFrame::MakeCut(const Eigen::Vector3d& p0, const Eigen::Vector3d& n0,
                                          const Eigen::Vector3d& ref_point_part_mm,
                                          const kinematics::SweepDirection& du,
                                          const kinematics::SweepDirection& dv) const {
  kinematics::CutPoint cut;
  cut.contact_in_tool_mm = R_.transpose() * (p0 - ref_point_part_mm);
  cut.axes = AxesFor(ref_point_part_mm);
  cut.nominal_point_mm = p0;
  cut.nominal_normal = n0.normalized();
  cut.du = du;
  cut.dv = dv;
  return cut;
}

double WrapTwoPi(double a) {
  a = std::fmod(a, 2.0 * kPi);
  if (a < 0) a += 2.0 * kPi;
  return a;
}

kinematics::AxisDelta Difference(const kinematics::AxisState& a, const kinematics::AxisState& b, double scale) {
  kinematics::AxisDelta d;
  d.x_mm = (a.x_mm - b.x_mm) * scale;
  d.y_mm = (a.y_mm - b.y_mm) * scale;
  d.z_mm = (a.z_mm - b.z_mm) * scale;
  d.a_rad = (a.a_rad - b.a_rad) * scale;
  d.b_rad = (a.b_rad - b.b_rad) * scale;
  d.c_rad = (a.c_rad - b.c_rad) * scale;
  return d;
}

}  // namespace tpcal::testpieces::internal
