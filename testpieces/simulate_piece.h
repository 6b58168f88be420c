// Virtual machining and measurement of a whole test piece: the composition of the probing plan
// (cut-state association) with the kinematics simulation primitive. Every plan point is solved
// exactly on the actual swept surface (kinematics::SimulateSurfacePoint, full chain, at the
// axis state, t_s and op of its cut), then measured by the virtual CMM (noise along the normal,
// probe-radius error, random placement).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "core/frames.h"
#include "core/point_set.h"
#include "core/status.h"
#include "kinematics/error_state.h"
#include "kinematics/machine_model.h"
#include "kinematics/simulate.h"
#include "testpieces/probing_plan.h"
#include "testpieces/process_effects.h"
#include "testpieces/test_piece.h"

namespace tpcal::testpieces {

struct PieceSimOptions {
  double noise_um = 0.0;               // 1-sigma CMM noise along the normal, >= 0
  std::uint64_t seed = 1;              // std::mt19937_64 seed (placement, then noise)
  double probe_radius_error_um = 0.0;  // actual - calibrated probe radius
  bool random_placement = false;       // else the CMM frame is the nominal DATUM frame
  double max_translation_mm = 300.0;   // random placement translation bound
  std::optional<ProbingOptions> density;  // default: the piece's config.probing
  kinematics::SimulateOptions solver;
  // Process effects (cutting-force deflection, servo reversal; testpieces/process_effects.h)
  // added along each point's nominal normal after the kinematic solve. Default: none.
  ProcessEffects process;
  Status Validate() const;
};

struct SimulationTruth {
  // p_in_cmm = cmm_from_part * p_in_part (with no placement: cmm_from_part = datum_from_part).
  Rigid3 cmm_from_part = Rigid3::Identity();
  std::vector<double> deviation_mm;  // per point: actual minus nominal along n0 (before CMM)
  std::vector<Eigen::Vector3d> actual_part_mm;  // per point: actual surface point, part frame
  ProbingPlan plan;                   // the plan that was simulated (nominal points, cut states)
};

struct SimulatedPiece {
  PointSet points;  // CMM frame: labels, xyz, normals (i, j, k); source "simulated <piece>"
  SimulationTruth truth;
};

// Errors: options validation; kInvalidArgument if `machine` is not SameNominalMachine as the
// piece's planning machine or `errors` belongs to another machine type; simulation failures
// (point index and feature named).
Result<SimulatedPiece> SimulatePiece(const TestPiece& piece, const kinematics::MachineModel& machine,
                                     const kinematics::ErrorState& errors, const PieceSimOptions& options);

}  // namespace tpcal::testpieces
