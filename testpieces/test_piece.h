// TestPiece: the one definition of a machined test piece that feeds the probing plan, the
// simulator, the NC program (gcode/), the inspection plan (gdt/) and the STEP model: nominal
// features, ordered operations with their axis states and times, the cut-state association of
// every feature, the datum frame and the inspection plan. A dimension is written once: in the
// piece's parameters (turning_piece.h, iso10791_pieces.h).
#pragma once

#include <Eigen/Core>
#include <string>
#include <variant>
#include <vector>

#include "core/frames.h"
#include "core/status.h"
#include "gdt/plan.h"
#include "kinematics/machine_model.h"
#include "kinematics/simulate.h"
#include "testpieces/cut_model.h"
#include "testpieces/iso10791_pieces.h"
#include "testpieces/nominal_feature.h"
#include "testpieces/program.h"
#include "testpieces/turning_piece.h"

namespace tpcal::testpieces {

enum class PieceKind { kTurning, kContourM1, kFaceMillingM2, kConeFrustum };
// "turning", "iso10791_m1", "iso10791_m2", "cone_frustum" (the YAML `piece:` values).
const char* PieceKindName(PieceKind k);

using PieceParams = std::variant<TurningPieceParams, ContourPieceParams, FaceMillingPieceParams, ConeFrustumParams>;
PieceKind KindOf(const PieceParams& p);

// Probing density. Defaults = seed 002 section 4.2: 16 points (every 22.5 deg) per face, one
// circle per face at the paper's heights / radii.
struct ProbingOptions {
  int points_per_circle = 16;    // turned faces, groove, bore, circle boss, cone sections
  int levels_per_face = 1;       // circles per cylinder / annulus / cone, lines per straight face
                                 // (1: the design height; more: spread over the probe-able band)
  int points_per_hole = 8;
  int levels_per_hole = 1;
  int points_per_line = 12;      // straight (M1) faces, per line
  int grid_per_side = 5;         // polygon planes (M1 floor strips, M2 passes): n x n grid
  double edge_margin_mm = 1.5;   // kept from patch edges (nose / corner fillets, chamfers)
  // The seed 002 plan (the defaults) and a dense scan (64 points per circle, 5 levels).
  static ProbingOptions Paper() { return {}; }
  static ProbingOptions Dense();
  Status Validate() const;
};

// Everything a test-piece configuration file holds (piece_config.h reads / writes it).
struct PieceConfig {
  PieceParams params = TurningPieceParams{};
  ProbingOptions probing;
  ProcessModel process;
  Status Validate() const;
};

struct TestPiece {
  PieceConfig config;
  std::string name;
  kinematics::MachineModel machine;  // the machine the operations were planned for (nominal)
  // Nominal datum frame in the part frame: p_in_part = part_from_datum * p_in_datum. The probing
  // plan CSV and the inspection plan nominals are in the datum frame.
  Rigid3 part_from_datum = Rigid3::Identity();
  std::vector<NominalFeature> features;
  std::vector<Operation> operations;   // operations[i].number == i + 1
  std::vector<FeatureCut> cuts;        // one per feature, same order
  gdt::InspectionPlan inspection;      // built from the same parameters (inspection_plan.h)

  PieceKind kind() const { return KindOf(config.params); }
  const NominalFeature* Feature(const std::string& name) const;
  const FeatureCut* Cut(const std::string& feature) const;
  double duration_s() const { return ProgramDuration(operations); }
};

// Builds the piece for `machine` (nominal geometry: its pivots, signs and axis chain). The
// turning piece and the cone need an ac_table machine; M1 and M2 any machine with X, Y, Z (and
// rotary axes at 0). Errors: config validation (kInvalidArgument naming the key), wrong machine
// type, inverse kinematics failures (strokes) naming the operation.
Result<TestPiece> MakeTestPiece(const PieceConfig& config, const kinematics::MachineModel& machine);

// Cut-state association (cut_model.h): the CutPoint of `feature`'s surface at the nominal
// surface point nearest to `p_part_mm` (any point near the feature, part frame). Errors:
// kInvalidArgument for an unknown feature or a point that no cut of that feature reaches
// (outside its machined band by more than 0.5 mm, or on the axis of a turned face).
Result<kinematics::CutPoint> CutPointAt(const TestPiece& piece, const std::string& feature,
                                        const Eigen::Vector3d& p_part_mm);
// The same for a point in the nominal datum frame (a measured point after datum alignment).
Result<kinematics::CutPoint> CutPointAtDatum(const TestPiece& piece, const std::string& feature,
                                             const Eigen::Vector3d& p_datum_mm);
// The same with the feature and its cut already looked up (piece.Feature, piece.Cut; both of
// `piece`): for associating many points of one feature.
Result<kinematics::CutPoint> CutPointAtDatum(const TestPiece& piece, const NominalFeature& feature,
                                             const FeatureCut& cut, const Eigen::Vector3d& p_datum_mm);

// True if the two models have the same nominal geometry (type, chain, pivots, motion signs), so
// a piece planned on one can be simulated on the other.
bool SameNominalMachine(const kinematics::MachineModel& a, const kinematics::MachineModel& b);

}  // namespace tpcal::testpieces
