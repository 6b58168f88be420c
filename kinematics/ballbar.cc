#include "kinematics/ballbar.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>
#include <string>

#include "core/units.h"

namespace tpcal::kinematics {
namespace {

// File-local names carry a Bb prefix (unity build: one translation unit per target).

constexpr double kBbCommandTol_mm = 1e-9;  // Newton stop on the nominal target (as datum_ball.h)
constexpr double kBbAxisClearance_mm = 1e-6;  // a ball nearer the axis line has no radial direction

AxisState BbWithLinear(AxisState s, const Eigen::Vector3d& q) {
  s.x_mm = q.x(), s.y_mm = q.y(), s.z_mm = q.z();
  return s;
}

Eigen::Vector3d BbNominalBall(const MachineModel& model, const BallbarGeometry& g, const AxisState& s) {
  return NominalToolPointInPart(model, s, g.installation.tool_ball_in_tool_mm);
}

// Linear commands putting the nominal tool ball on `target_in_part` with the rotary commands of
// `s`. The nominal chain is affine in (X, Y, Z) at fixed rotary commands, so the central
// difference over 1 mm is its exact Jacobian and Newton converges in one step.
Result<Eigen::Vector3d> BbSolveLinear(const MachineModel& model, const BallbarGeometry& g, const AxisState& s,
                                      const Eigen::Vector3d& target_in_part) {
  // Three steps: the first solves the affine problem, the others polish it to rounding.
  Eigen::Vector3d q = Eigen::Vector3d::Zero();
  for (int it = 0; it < 3; ++it) {
    const Eigen::Vector3d r = BbNominalBall(model, g, BbWithLinear(s, q)) - target_in_part;
    Eigen::Matrix3d A;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d d = Eigen::Vector3d::Unit(k);
      A.col(k) = 0.5 * (BbNominalBall(model, g, BbWithLinear(s, q + d)) - BbNominalBall(model, g, BbWithLinear(s, q - d)));
    }
    q -= A.partialPivLu().solve(r);
  }
  if ((BbNominalBall(model, g, BbWithLinear(s, q)) - target_in_part).norm() <= kBbCommandTol_mm) return q;
  return Status(StatusCode::kNotConverged, "ball bar '" + g.installation.name +
                                               "': no linear commands reach the tool ball's nominal target");
}

// The turned axis line in the part frame: part_from_tool from `angle 0` to `angle 90 deg` is a
// quarter turn of the tool about it (ISO 841: + command turns the tool + relative to the part).
void BbAxisLineInPart(const MachineModel& model, const AxisState& s0, Axis axis, Eigen::Vector3d* point,
                      Eigen::Vector3d* direction) {
  AxisState s90 = s0;
  SetPosition(&s90, axis, DegToRad(90.0));
  const Rigid3 p0 = NominalPartFromTool(model, s0), p90 = NominalPartFromTool(model, s90);
  const Rigid3 motion = p90 * p0.inverse();  // part-frame motion of the tool
  const Eigen::Matrix3d R = motion.rotation();
  const Eigen::Matrix3d skew = 0.5 * (R - R.transpose());  // sin(90 deg) [a]x
  *direction = Eigen::Vector3d(skew(2, 1), skew(0, 2), skew(1, 0)).normalized();
  // Fixed points: (I - R) c = t; rank 2, the minimum-norm solution is the line point nearest 0.
  *point = (Eigen::Matrix3d::Identity() - R).jacobiSvd(Eigen::ComputeFullU | Eigen::ComputeFullV).solve(motion.translation());
}

}  // namespace

Result<BallbarGeometry> MakeBallbarGeometry(const MachineModel& model, const BallbarInstallation& installation) {
  BallbarGeometry g;
  g.installation = installation;
  const std::string what = "ball bar '" + installation.name + "'";
  for (const auto& [axis, deg] : installation.hold_deg) {
    if (!model.HasAxis(axis))
      return Status(StatusCode::kInvalidArgument, what + ": hold_deg names axis " + std::string(1, AxisLetter(axis)) +
                                                      ", which the machine does not have");
    SetPosition(&g.hold, axis, DegToRad(deg));
  }
  if (installation.kind == BallbarKind::kCircle) return g;
  const Axis axis = installation.axis;
  if (!model.HasAxis(axis) || !IsRotary(axis))
    return Status(StatusCode::kInvalidArgument,
                  what + ": the machine has no rotary axis " + std::string(1, AxisLetter(axis)));
  g.tool_side = model.links[static_cast<std::size_t>(model.LinkIndex(axis))].branch == Branch::kTool;
  AxisState s0 = g.hold;
  SetPosition(&s0, axis, 0.0);
  Eigen::Vector3d point_part, dir_part;
  BbAxisLineInPart(model, s0, axis, &point_part, &dir_part);
  if (g.tool_side) {  // the same line in the tool frame at the turned axis = 0 (X, Y, Z = 0)
    const Rigid3 tool_from_part = NominalPartFromTool(model, s0).inverse();
    g.axis_point_mm = tool_from_part * point_part;
    g.axis_direction = tool_from_part.rotation() * dir_part;
  } else {
    g.axis_point_mm = point_part;
    g.axis_direction = dir_part;
  }
  const Eigen::Vector3d& a = g.axis_direction;
  if (installation.kind == BallbarKind::kAxial) {
    g.bar_direction = a;
    return g;
  }
  const Eigen::Vector3d ball =
      g.tool_side ? installation.tool_ball_in_tool_mm : installation.workpiece_ball_in_part_mm;
  const Eigen::Vector3d r = ball - g.axis_point_mm;
  const Eigen::Vector3d r_perp = r - r.dot(a) * a;
  if (!(r_perp.norm() > kBbAxisClearance_mm))
    return Status(StatusCode::kInvalidArgument,
                  what + ": the " + (g.tool_side ? "tool" : "workpiece") + " ball lies on the " +
                      std::string(1, AxisLetter(axis)) + " axis line; a " + BallbarKindName(installation.kind) +
                      " installation needs it off the axis");
  const Eigen::Vector3d radial = r_perp.normalized();
  g.bar_direction = installation.kind == BallbarKind::kRadial ? radial : Eigen::Vector3d(a.cross(radial));
  return g;
}

Eigen::Vector3d BallbarTargetInPart(const MachineModel& model, const BallbarGeometry& g, double angle_deg) {
  const BallbarInstallation& inst = g.installation;
  const Eigen::Vector3d& w = inst.workpiece_ball_in_part_mm;
  if (inst.kind == BallbarKind::kCircle) {
    // The commands centring the tool ball on w plus the circle offset in machine axes: the nominal
    // chain is affine in (X, Y, Z), so the offset moves the tool ball by p1 - p0 in the part frame.
    AxisState s = g.hold;
    const Eigen::Vector3d p0 = NominalToolPointInPart(model, s, inst.tool_ball_in_tool_mm);
    const double phi = DegToRad(angle_deg);
    Eigen::Vector3d offset = Eigen::Vector3d::Zero();
    const int i1 = inst.plane == BallbarPlane::kXY ? 0 : inst.plane == BallbarPlane::kYZ ? 1 : 2;
    const int i2 = (i1 + 1) % 3;
    offset(i1) = inst.nominal_length_mm * std::cos(phi);
    offset(i2) = inst.nominal_length_mm * std::sin(phi);
    const Eigen::Vector3d p1 = NominalToolPointInPart(model, BbWithLinear(s, offset), inst.tool_ball_in_tool_mm);
    return w + (p1 - p0);
  }
  Eigen::Vector3d d = g.bar_direction;
  if (g.tool_side) {
    AxisState s = g.hold;
    SetPosition(&s, inst.axis, DegToRad(angle_deg));
    d = NominalPartFromTool(model, s).rotation() * d;
  }
  return w + inst.sense * inst.nominal_length_mm * d;
}

Result<AxisState> BallbarCommand(const MachineModel& model, const BallbarGeometry& g, double angle_deg, double t_s) {
  AxisState s = g.hold;
  s.t_s = t_s;
  if (g.installation.kind != BallbarKind::kCircle) SetPosition(&s, g.installation.axis, DegToRad(angle_deg));
  Result<Eigen::Vector3d> q = BbSolveLinear(model, g, s, BallbarTargetInPart(model, g, angle_deg));
  TPCAL_RETURN_IF_ERROR(q);
  return BbWithLinear(s, *q);
}

double BallbarLengthMm(const MachineModel& model, const ErrorState& errors, const BallbarGeometry& g,
                       const AxisState& axes, Workspace* ws) {
  const Eigen::Vector3d tool_ball_in_part = ToolPointInPart(model, errors, axes, g.installation.tool_ball_in_tool_mm, ws);
  return (tool_ball_in_part - g.installation.workpiece_ball_in_part_mm).norm();
}

Result<double> SimulateBallbarDlUm(const MachineModel& model, const ErrorState& errors, const BallbarGeometry& g,
                                   double angle_deg, double t_s, Workspace* ws) {
  Result<AxisState> axes = BallbarCommand(model, g, angle_deg, t_s);
  TPCAL_RETURN_IF_ERROR(axes);
  return MmToUm(BallbarLengthMm(model, errors, g, *axes, ws) - g.installation.nominal_length_mm);
}

}  // namespace tpcal::kinematics
