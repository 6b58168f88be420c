// Cut-state association (cut_model.h, test_piece.h CutPointAt).
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/units.h"
#include "kinematics/inverse_kinematics.h"
#include "testpieces/internal/planning.h"

namespace tpcal::testpieces {
namespace internal {
namespace {

// A point belongs to a cut if it lies within this distance (mm) of the cut's reach: tolerates
// measured points (form errors of microns) but rejects points of another surface.
constexpr double kReachTol_mm = 0.5;

const Move* FindMove(const TestPiece& piece, const CutRef& ref, const Spindle** spindle) {
  if (ref.op < 1 || ref.op > static_cast<int>(piece.operations.size())) return nullptr;
  const Operation& op = piece.operations[ref.op - 1];
  if (ref.pass < 0 || ref.pass >= static_cast<int>(op.passes.size())) return nullptr;
  const Pass& pass = op.passes[ref.pass];
  if (ref.move < 0 || ref.move >= static_cast<int>(pass.moves.size())) return nullptr;
  if (spindle) *spindle = &pass.spindle;
  return &pass.moves[ref.move];
}

Status BadRef(const std::string& feature) {
  return {StatusCode::kInternal, "feature " + feature + ": cut refers to a move that does not exist"};
}

Status OutOfReach(const std::string& feature, const std::string& why) {
  return {StatusCode::kInvalidArgument, "feature " + feature + ": point not reached by its cut (" + why + ")"};
}

Result<kinematics::CutPoint> EvaluateTurned(const TestPiece& piece, const NominalFeature& f, const TurnedCut& cut,
                                            const Eigen::Vector3d& p) {
  TPCAL_ASSIGN_OR_RETURN(const Projection proj, ProjectOnto(f, p));
  const Eigen::Vector3d p0 = proj.point_mm;
  const Eigen::Vector3d n0 = proj.normal;
  const double radius = std::hypot(p0.x(), p0.y());
  if (radius < 1e-9) return OutOfReach(f.name, "on the turning axis");
  const double coord = cut.radial_feed ? radius : p0.z();
  const double span = cut.coord_end_mm - cut.coord_start_mm;
  const double sigma = (coord - cut.coord_start_mm) / span;
  const double tol = kReachTol_mm / std::abs(span);
  if (sigma < -tol || sigma > 1.0 + tol) {
    return OutOfReach(f.name, std::string(cut.radial_feed ? "radius " : "height ") + std::to_string(coord) +
                                  " mm outside the feed from " + std::to_string(cut.coord_start_mm) + " to " +
                                  std::to_string(cut.coord_end_mm) + " mm");
  }
  const Spindle* spindle = nullptr;
  const Move* move = FindMove(piece, cut.ref, &spindle);
  if (!move) return BadRef(f.name);
  kinematics::AxisState rotary;
  rotary.a_rad = cut.a_rad;
  rotary.c_rad = WrapTwoPi(std::atan2(p0.y(), p0.x()) - cut.tool_azimuth_rad);
  rotary.t_s = TimeAtFraction(*move, sigma, *spindle);
  rotary.op = cut.ref.op;
  const Eigen::Vector3d nose_center = p0 + cut.nose_radius_mm * n0;
  kinematics::SweepDirection du, dv;
  // du: the feed move, per mm of the tool reference point; dv: the table spin, per rad.
  const double length = std::sqrt(std::pow(move->end.x_mm - move->start.x_mm, 2) +
                                   std::pow(move->end.y_mm - move->start.y_mm, 2) +
                                   std::pow(move->end.z_mm - move->start.z_mm, 2));
  if (!(length > 0)) return BadRef(f.name);
  du.axes = Difference(move->end, move->start, 1.0 / length);
  du.axes.a_rad = du.axes.b_rad = du.axes.c_rad = 0.0;
  dv.axes.c_rad = 1.0;
  return MakeCutPoint(piece.machine, p0, n0, nose_center, rotary, du, dv);
}

struct ElementHit {
  bool valid = false;
  int op = 0;
  double mismatch_mm = std::numeric_limits<double>::infinity();
  double time_s = 0.0;
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();
  Eigen::Vector3d path_tangent = Eigen::Vector3d::Zero();  // tip velocity per unit of the parameter
  Eigen::Vector3d across = Eigen::Vector3d::Zero();        // end face: in-plane, normal to the path
};

Result<kinematics::CutPoint> EvaluatePath(const TestPiece& piece, const NominalFeature& f, const PathMillCut& cut,
                                          const Eigen::Vector3d& p) {
  TPCAL_ASSIGN_OR_RETURN(const Projection proj, ProjectOnto(f, p));
  const Eigen::Vector3d p0 = proj.point_mm;
  const Eigen::Vector3d n0 = proj.normal;
  const Eigen::Vector3d a = cut.tool_axis;
  const double flat_radius = cut.tool_radius_mm - cut.corner_radius_mm;
  ElementHit best;
  for (const PathElement& e : cut.elements) {
    const Spindle* spindle = nullptr;
    const Move* move = FindMove(piece, e.ref, &spindle);
    if (!move) return BadRef(f.name);
    ElementHit hit;
    double sigma = 0.0, tol = 0.0;
    if (!e.arc) {
      const Eigen::Vector3d d = e.end_tip_mm - e.start_tip_mm;
      const double length = d.norm();
      if (!(length > 0)) return BadRef(f.name);
      const Eigen::Vector3d dir = d / length;
      sigma = (p0 - e.start_tip_mm).dot(dir) / length;
      tol = kReachTol_mm / length;
      hit.tip = e.start_tip_mm + sigma * d;
      hit.path_tangent = dir;  // per mm
      hit.across = a.cross(dir);
    } else {
      Eigen::Vector3d r = p0 - e.center_mm;
      r -= r.dot(a) * a;
      if (r.norm() < 1e-9) continue;
      const Eigen::Vector3d dirp = r.normalized();
      double alpha = std::atan2(e.start_dir.cross(dirp).dot(a), e.start_dir.dot(dirp));  // CCW about a
      alpha = e.clockwise ? WrapTwoPi(-alpha) : WrapTwoPi(alpha);
      // Close to a full circle, a point just before the start belongs to the end.
      sigma = alpha / e.angle_rad;
      tol = kReachTol_mm / (e.radius_mm * e.angle_rad);
      if (sigma > 1.0 + tol) sigma -= 2.0 * kPi / e.angle_rad;  // just before the start
      hit.tip = e.center_mm + e.radius_mm * dirp;
      const Eigen::Vector3d tangent = (e.clockwise ? -1.0 : 1.0) * a.cross(dirp);
      hit.path_tangent = e.radius_mm * tangent;  // per rad
      hit.across = dirp;
    }
    if (sigma < -tol || sigma > 1.0 + tol) continue;
    const Eigen::Vector3d offset = p0 - hit.tip;
    const double along_axis = offset.dot(a);
    const double lateral = (offset - along_axis * a).norm();
    if (cut.end_face) {
      if (std::abs(along_axis) > kReachTol_mm || lateral > flat_radius + 1e-9) continue;
      hit.mismatch_mm = std::abs(along_axis);
    } else {
      if (along_axis < -kReachTol_mm) continue;
      hit.mismatch_mm = std::abs(lateral - cut.tool_radius_mm);
      if (hit.mismatch_mm > kReachTol_mm) continue;
    }
    hit.valid = true;
    hit.op = e.ref.op;
    hit.time_s = TimeAtFraction(*move, sigma, *spindle);
    // Side: the closest element wins (ties: the later one); end face: the last to pass.
    const bool better = !best.valid ||
                        (cut.end_face ? hit.time_s > best.time_s
                                      : (hit.mismatch_mm < best.mismatch_mm - 1e-9 ||
                                         (hit.mismatch_mm <= best.mismatch_mm + 1e-9 && hit.time_s > best.time_s)));
    if (better) best = hit;
  }
  if (!best.valid) return OutOfReach(f.name, cut.end_face ? "not under the flat end of any pass" : "no pass touches it");
  kinematics::AxisState rotary = cut.rotary;
  rotary.t_s = best.time_s;
  rotary.op = best.op;
  TPCAL_ASSIGN_OR_RETURN(const RotaryFrame frame, RotaryFrame::At(piece.machine, rotary));
  kinematics::SweepDirection du, dv;
  du.axes = frame.DeltaFor(best.path_tangent);
  dv.contact_in_tool_mm = frame.part_from_tool_rotation().transpose() * (cut.end_face ? best.across : a);
  return frame.MakeCut(p0, n0, best.tip, du, dv);
}

Result<kinematics::CutPoint> EvaluatePlunge(const TestPiece& piece, const NominalFeature& f, const PlungeCut& cut,
                                            const Eigen::Vector3d& p) {
  TPCAL_ASSIGN_OR_RETURN(const Projection proj, ProjectOnto(f, p));
  const Eigen::Vector3d p0 = proj.point_mm;
  const Eigen::Vector3d n0 = proj.normal;
  const double depth = (cut.entry_mm - p0).dot(cut.axis);
  const double sigma = depth / cut.depth_mm;
  const double tol = kReachTol_mm / cut.depth_mm;
  if (sigma < -tol || sigma > 1.0 + tol) {
    return OutOfReach(f.name, "depth " + std::to_string(depth) + " mm outside the plunge");
  }
  const Spindle* spindle = nullptr;
  const Move* move = FindMove(piece, cut.ref, &spindle);
  if (!move) return BadRef(f.name);
  kinematics::AxisState rotary = cut.rotary;
  rotary.t_s = TimeAtFraction(*move, sigma, *spindle);
  rotary.op = cut.ref.op;
  const Eigen::Vector3d tip = cut.entry_mm - depth * cut.axis;
  TPCAL_ASSIGN_OR_RETURN(const RotaryFrame frame, RotaryFrame::At(piece.machine, rotary));
  kinematics::SweepDirection du, dv;
  du.axes = frame.DeltaFor(-cut.axis);
  // the cutting edges turning, per rad
  dv.contact_in_tool_mm = frame.part_from_tool_rotation().transpose() * cut.axis.cross(p0 - tip);
  return frame.MakeCut(p0, n0, tip, du, dv);
}

// Tool pose of the cone flank pass at azimuth theta: tip position and rotary state.
struct FlankPose {
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();
  Eigen::Vector3d generatrix = Eigen::Vector3d::UnitZ();
  kinematics::AxisState rotary;
};

Result<FlankPose> FlankPoseAt(const TestPiece& piece, const NominalFeature& cone, const FlankMillCut& cut,
                              double theta, const kinematics::AxisState* near) {
  const double alpha = cone.half_angle_rad;
  const Eigen::Vector3d er = std::cos(theta) * cone.ref_dir + std::sin(theta) * cone.v_dir();
  FlankPose pose;
  pose.generatrix = std::cos(alpha) * cone.axis - std::sin(alpha) * er;
  const SurfaceCoords at_tip{theta, cut.h_tip_mm};
  pose.tip = PointAt(cone, at_tip) + cut.tool_radius_mm * NormalAt(cone, at_tip);
  const double c_hint = near ? near->c_rad : 0.0;
  TPCAL_ASSIGN_OR_RETURN(const std::vector<kinematics::AxisState> sols,
                         kinematics::RotaryAnglesForToolAxis(piece.machine, pose.generatrix, c_hint,
                                                             kinematics::InverseKinematicsOptions{false}));
  const kinematics::AxisState* chosen = nullptr;
  for (const auto& s : sols) {
    const double tilt = s.a_rad + s.b_rad;  // the machine has one of them
    if ((cut.negative_tilt && tilt <= 0) || (!cut.negative_tilt && tilt >= 0)) chosen = &s;
  }
  if (!chosen) chosen = &sols.front();
  pose.rotary = *chosen;
  pose.rotary.c_rad = WrapTwoPi(pose.rotary.c_rad);
  if (near) {  // unwrap C next to the reference state
    pose.rotary.c_rad = near->c_rad + std::remainder(pose.rotary.c_rad - near->c_rad, 2.0 * kPi);
  }
  return pose;
}

Result<kinematics::CutPoint> EvaluateFlank(const TestPiece& piece, const NominalFeature& f, const FlankMillCut& cut,
                                           const Eigen::Vector3d& p) {
  if (f.type != SurfaceType::kCone) return Status(StatusCode::kInternal, "flank cut on a non-cone feature");
  TPCAL_ASSIGN_OR_RETURN(const Projection proj, ProjectOnto(f, p));
  const double theta = proj.coords.s1;
  const double h = proj.coords.s2;
  if (h < cut.h_tip_mm - kReachTol_mm) return OutOfReach(f.name, "below the tool tip");
  double travelled = cut.counter_clockwise ? WrapTwoPi(theta - cut.theta_start_rad)
                                           : WrapTwoPi(cut.theta_start_rad - theta);
  const double sigma = travelled / (2.0 * kPi);
  // Time: interpolate over the discretised moves of the pass.
  const Spindle* spindle = nullptr;
  const Move* first = FindMove(piece, cut.ref, &spindle);
  CutRef last_ref = cut.ref;
  last_ref.move += cut.steps - 1;
  const Move* last = FindMove(piece, last_ref, nullptr);
  if (!first || !last) return BadRef(f.name);
  const double k = std::min(sigma * cut.steps, cut.steps - 1e-12);
  const int index = static_cast<int>(std::floor(k));
  const Move& m = *(first + index);
  const double t = TimeAtFraction(m, k - index, *spindle);

  TPCAL_ASSIGN_OR_RETURN(FlankPose pose, FlankPoseAt(piece, f, cut, theta, nullptr));
  pose.rotary.t_s = t;
  pose.rotary.op = cut.ref.op;
  const Eigen::Vector3d p0 = proj.point_mm;
  const Eigen::Vector3d n0 = proj.normal;
  // du: along the pass (per rad of theta) with the contact following the nominal contact line;
  // central differences of the exact poses (step 1e-5 rad: truncation ~1e-10 relative).
  constexpr double kStep = 1e-5;
  kinematics::SweepDirection du, dv;
  kinematics::AxisState axes[2];
  Eigen::Vector3d contact[2];
  for (int s = 0; s < 2; ++s) {
    const double th = theta + (s == 0 ? -kStep : kStep);
    TPCAL_ASSIGN_OR_RETURN(const FlankPose q, FlankPoseAt(piece, f, cut, th, &pose.rotary));
    const SurfaceCoords c{th, h};
    TPCAL_ASSIGN_OR_RETURN(axes[s], AxesForRefPoint(piece.machine, q.tip, q.rotary));
    contact[s] = PartFromToolRotation(piece.machine, q.rotary).transpose() * (PointAt(f, c) - q.tip);
  }
  du.axes = Difference(axes[1], axes[0], 1.0 / (2.0 * kStep));
  du.contact_in_tool_mm = (contact[1] - contact[0]) / (2.0 * kStep);
  // dv: along the tool axis (the generatrix), expressed in the tool frame.
  const Eigen::Matrix3d R = PartFromToolRotation(piece.machine, pose.rotary);
  dv.contact_in_tool_mm = R.transpose() * pose.generatrix;
  return MakeCutPoint(piece.machine, p0, n0, pose.tip, pose.rotary, du, dv);
}

}  // namespace

Result<kinematics::CutPoint> EvaluateCut(const TestPiece& piece, const NominalFeature& feature,
                                         const CutModel& model, const Eigen::Vector3d& p_part_mm) {
  if (!p_part_mm.allFinite()) return Status(StatusCode::kInvalidArgument, "non-finite point");
  if (const auto* m = std::get_if<TurnedCut>(&model)) return EvaluateTurned(piece, feature, *m, p_part_mm);
  if (const auto* m = std::get_if<PathMillCut>(&model)) return EvaluatePath(piece, feature, *m, p_part_mm);
  if (const auto* m = std::get_if<PlungeCut>(&model)) return EvaluatePlunge(piece, feature, *m, p_part_mm);
  if (const auto* m = std::get_if<FlankMillCut>(&model)) return EvaluateFlank(piece, feature, *m, p_part_mm);
  return Status(StatusCode::kInternal, "unknown cut model");
}

}  // namespace internal

Result<kinematics::CutPoint> CutPointAt(const TestPiece& piece, const std::string& feature,
                                        const Eigen::Vector3d& p_part_mm) {
  const NominalFeature* f = piece.Feature(feature);
  const FeatureCut* cut = piece.Cut(feature);
  if (!f || !cut) {
    return Status(StatusCode::kInvalidArgument, "test piece '" + piece.name + "' has no feature '" + feature + "'");
  }
  return internal::EvaluateCut(piece, *f, cut->model, p_part_mm);
}

Result<kinematics::CutPoint> CutPointAtDatum(const TestPiece& piece, const std::string& feature,
                                             const Eigen::Vector3d& p_datum_mm) {
  return CutPointAt(piece, feature, piece.part_from_datum * p_datum_mm);
}

Result<kinematics::CutPoint> CutPointAtDatum(const TestPiece& piece, const NominalFeature& feature,
                                             const FeatureCut& cut, const Eigen::Vector3d& p_datum_mm) {
  return internal::EvaluateCut(piece, feature, cut.model, piece.part_from_datum * p_datum_mm);
}

}  // namespace tpcal::testpieces
