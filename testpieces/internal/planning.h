// Internal planning helpers shared by the piece builders and the cut-state association
// (not part of the public API).
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <string>
#include <utility>

#include "core/status.h"
#include "kinematics/axis_state.h"
#include "kinematics/machine_model.h"
#include "kinematics/simulate.h"
#include "testpieces/test_piece.h"

#define TPCAL_TP_CONCAT_INNER(a, b) a##b
#define TPCAL_TP_CONCAT(a, b) TPCAL_TP_CONCAT_INNER(a, b)
// lhs = value of a Result expression, or return its Status.
#define TPCAL_ASSIGN_OR_RETURN(lhs, expr)                                   \
  auto TPCAL_TP_CONCAT(tpcal_result_, __LINE__) = (expr);                   \
  if (!TPCAL_TP_CONCAT(tpcal_result_, __LINE__).ok())                       \
    return TPCAL_TP_CONCAT(tpcal_result_, __LINE__).status();               \
  lhs = std::move(TPCAL_TP_CONCAT(tpcal_result_, __LINE__)).value()

namespace tpcal::testpieces::internal {

// Rotary part of a state (A, B, C, t_s, op kept; X, Y, Z zeroed).
kinematics::AxisState RotaryOnly(const kinematics::AxisState& s);

// Rotation of part_from_tool at the rotary state (nominal machine).
Eigen::Matrix3d PartFromToolRotation(const kinematics::MachineModel& machine, const kinematics::AxisState& rotary);

// Axis commands that put the tool reference point at `ref_point_part_mm` (nominal).
Result<kinematics::AxisState> AxesForRefPoint(const kinematics::MachineModel& machine,
                                              const Eigen::Vector3d& ref_point_part_mm,
                                              const kinematics::AxisState& rotary, bool check_strokes = false);

// Axis increments per unit displacement of the tool reference point along `dir_part` (part
// frame, not necessarily unit) at fixed rotary axes (exact: the nominal chain is affine in X, Y, Z).
Result<kinematics::AxisDelta> LinearDeltaFor(const kinematics::MachineModel& machine,
                                             const kinematics::AxisState& rotary, const Eigen::Vector3d& dir_part);

// A CutPoint: surface point p0 with outward normal n0 cut by the tool whose reference point is
// at `ref_point_part_mm` at `rotary` (t_s, op included); sweeps du, dv given.
Result<kinematics::CutPoint> MakeCutPoint(const kinematics::MachineModel& machine, const Eigen::Vector3d& p0,
                                          const Eigen::Vector3d& n0, const Eigen::Vector3d& ref_point_part_mm,
                                          const kinematics::AxisState& rotary, const kinematics::SweepDirection& du,
                                          const kinematics::SweepDirection& dv);

// The nominal chain at one rotary state, solved once for every tool reference point and sweep
// direction needed there (association evaluates several per surface point): the chain is affine
// in X, Y, Z, p_ref = ref0 + M [x y z]. Same arithmetic as AxesForRefPoint / LinearDeltaFor /
// MakeCutPoint, so the results are identical.
class RotaryFrame {
 public:
  // Errors: kDegenerate if the linear axes do not span space at `rotary`.
  static Result<RotaryFrame> At(const kinematics::MachineModel& machine, const kinematics::AxisState& rotary);
  kinematics::AxisState AxesFor(const Eigen::Vector3d& ref_point_part_mm) const;  // t_s, op of `rotary`
  kinematics::AxisDelta DeltaFor(const Eigen::Vector3d& dir_part) const;
  const Eigen::Matrix3d& part_from_tool_rotation() const { return R_; }
  // MakeCutPoint at this rotary state.
  kinematics::CutPoint MakeCut(const Eigen::Vector3d& p0, const Eigen::Vector3d& n0,
                               const Eigen::Vector3d& ref_point_part_mm, const kinematics::SweepDirection& du,
                               const kinematics::SweepDirection& dv) const;

 private:
  kinematics::AxisState rotary_;
  Eigen::Matrix3d R_;
  Eigen::Vector3d ref0_mm_;
  Eigen::FullPivLU<Eigen::Matrix3d> lu_;
};

double WrapTwoPi(double a);
kinematics::AxisDelta Difference(const kinematics::AxisState& a, const kinematics::AxisState& b, double scale);

// Piece builders (one .cc each). The config is validated by MakeTestPiece.
Result<TestPiece> BuildTurningPiece(const PieceConfig& config, const kinematics::MachineModel& machine);
Result<TestPiece> BuildContourPiece(const PieceConfig& config, const kinematics::MachineModel& machine);
Result<TestPiece> BuildFaceMillingPiece(const PieceConfig& config, const kinematics::MachineModel& machine);
Result<TestPiece> BuildConeFrustumPiece(const PieceConfig& config, const kinematics::MachineModel& machine);

// Cut-state association per model (association.cc).
Result<kinematics::CutPoint> EvaluateCut(const TestPiece& piece, const NominalFeature& feature,
                                         const CutModel& model, const Eigen::Vector3d& p_part_mm);

}  // namespace tpcal::testpieces::internal
