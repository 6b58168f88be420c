#include "testpieces/test_piece.h"

#include "testpieces/inspection_plan.h"
#include "testpieces/internal/planning.h"

namespace tpcal::testpieces {

const char* PieceKindName(PieceKind k) {
  switch (k) {
    case PieceKind::kTurning: return "turning";
    case PieceKind::kContourM1: return "iso10791_m1";
    case PieceKind::kFaceMillingM2: return "iso10791_m2";
    case PieceKind::kConeFrustum: return "cone_frustum";
  }
  return "?";
}

PieceKind KindOf(const PieceParams& p) {
  switch (p.index()) {
    case 0: return PieceKind::kTurning;
    case 1: return PieceKind::kContourM1;
    case 2: return PieceKind::kFaceMillingM2;
    default: return PieceKind::kConeFrustum;
  }
}

ProbingOptions ProbingOptions::Dense() {
  ProbingOptions o;
  o.points_per_circle = 64;
  o.levels_per_face = 5;
  o.points_per_hole = 16;
  o.levels_per_hole = 3;
  o.points_per_line = 40;
  o.grid_per_side = 12;
  return o;
}

Status ProbingOptions::Validate() const {
  if (points_per_circle < 3) return {StatusCode::kInvalidArgument, "probing.points_per_circle must be >= 3"};
  if (levels_per_face < 1) return {StatusCode::kInvalidArgument, "probing.levels_per_face must be >= 1"};
  if (points_per_hole < 3) return {StatusCode::kInvalidArgument, "probing.points_per_hole must be >= 3"};
  if (levels_per_hole < 1) return {StatusCode::kInvalidArgument, "probing.levels_per_hole must be >= 1"};
  if (points_per_line < 2) return {StatusCode::kInvalidArgument, "probing.points_per_line must be >= 2"};
  if (grid_per_side < 2) return {StatusCode::kInvalidArgument, "probing.grid_per_side must be >= 2"};
  if (!(edge_margin_mm >= 0)) return {StatusCode::kInvalidArgument, "probing.edge_margin_mm must be >= 0"};
  return Status::Ok();
}

Status PieceConfig::Validate() const {
  TPCAL_RETURN_IF_ERROR(probing.Validate());
  TPCAL_RETURN_IF_ERROR(process.Validate());
  return std::visit([](const auto& p) { return p.Validate(); }, params);
}

const NominalFeature* TestPiece::Feature(const std::string& n) const { return FindFeature(features, n); }

const FeatureCut* TestPiece::Cut(const std::string& feature) const {
  for (const auto& c : cuts) {
    if (c.feature == feature) return &c;
  }
  return nullptr;
}

bool SameNominalMachine(const kinematics::MachineModel& a, const kinematics::MachineModel& b) {
  if (a.type != b.type || a.num_workpiece_links != b.num_workpiece_links || a.links.size() != b.links.size()) {
    return false;
  }
  for (std::size_t i = 0; i < a.links.size(); ++i) {
    const auto& la = a.links[i];
    const auto& lb = b.links[i];
    if (la.axis != lb.axis || la.branch != lb.branch || (la.pivot_mm - lb.pivot_mm).norm() > 1e-12) return false;
  }
  return true;
}

Result<TestPiece> MakeTestPiece(const PieceConfig& config, const kinematics::MachineModel& machine) {
  TPCAL_RETURN_IF_ERROR(config.Validate());
  TPCAL_RETURN_IF_ERROR(machine.Validate());
  Result<TestPiece> piece = Status(StatusCode::kInternal, "no builder");
  switch (KindOf(config.params)) {
    case PieceKind::kTurning: piece = internal::BuildTurningPiece(config, machine); break;
    case PieceKind::kContourM1: piece = internal::BuildContourPiece(config, machine); break;
    case PieceKind::kFaceMillingM2: piece = internal::BuildFaceMillingPiece(config, machine); break;
    case PieceKind::kConeFrustum: piece = internal::BuildConeFrustumPiece(config, machine); break;
  }
  if (!piece.ok()) return piece.status();
  for (const auto& f : piece->features) TPCAL_RETURN_IF_ERROR(ValidateFeature(f));
  TPCAL_ASSIGN_OR_RETURN(piece->inspection, BuildInspectionPlan(*piece));
  return piece;
}

}  // namespace tpcal::testpieces
