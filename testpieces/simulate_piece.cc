#include "testpieces/simulate_piece.h"

#include <random>

#include "kinematics/forward_kinematics.h"
#include "kinematics/virtual_cmm.h"

namespace tpcal::testpieces {

Status PieceSimOptions::Validate() const {
  if (!(noise_um >= 0)) return {StatusCode::kInvalidArgument, "simulation noise_um must be >= 0"};
  if (!std::isfinite(probe_radius_error_um)) {
    return {StatusCode::kInvalidArgument, "simulation probe_radius_error_um must be finite"};
  }
  if (!(max_translation_mm >= 0)) return {StatusCode::kInvalidArgument, "simulation max_translation_mm must be >= 0"};
  if (density) TPCAL_RETURN_IF_ERROR(density->Validate());
  TPCAL_RETURN_IF_ERROR(process.Validate());
  return solver.Validate();
}

Result<SimulatedPiece> SimulatePiece(const TestPiece& piece, const kinematics::MachineModel& machine,
                                     const kinematics::ErrorState& errors, const PieceSimOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  if (!SameNominalMachine(machine, piece.machine)) {
    return Status(StatusCode::kInvalidArgument, "test piece '" + piece.name +
                                                    "' was planned for another machine (type, chain or pivots differ)");
  }
  if (errors.machine_type() != machine.type || errors.num_links() != machine.num_links()) {
    return Status(StatusCode::kInvalidArgument, "error state belongs to another machine type");
  }
  auto plan = MakeProbingPlan(piece, options.density.value_or(piece.config.probing));
  if (!plan.ok()) return plan.status();

  SimulatedPiece out;
  const Rigid3 datum_from_part = piece.part_from_datum.inverse();
  PointSet actual_datum;
  actual_datum.source = "simulated " + piece.name;
  kinematics::Workspace ws;
  out.truth.deviation_mm.reserve(plan->points.size());
  for (std::size_t i = 0; i < plan->points.size(); ++i) {
    const PlanPoint& pp = plan->points[i];
    auto s = kinematics::SimulateSurfacePoint(machine, errors, pp.cut, &ws, options.solver);
    if (!s.ok()) {
      return s.status().WithContext("simulating point " + std::to_string(i) + " of feature " + pp.feature);
    }
    if (!options.process.empty()) {
      auto extra_mm = ProcessDeviationMm(piece, machine, pp, options.process);
      if (!extra_mm.ok()) return extra_mm.status().WithContext("process effects at point " + std::to_string(i));
      s->deviation_mm += *extra_mm;
      s->point_mm += *extra_mm * pp.normal_part;
    }
    out.truth.deviation_mm.push_back(s->deviation_mm);
    out.truth.actual_part_mm.push_back(s->point_mm);
    actual_datum.xyz_mm.push_back(datum_from_part * s->point_mm);
    actual_datum.normal.push_back(datum_from_part.linear() * pp.normal_part);
    actual_datum.feature.push_back(actual_datum.InternFeature(pp.feature));
  }
  kinematics::VirtualCmmOptions cmm;
  cmm.noise_sigma_um = options.noise_um;
  cmm.probe_radius_error_um = options.probe_radius_error_um;
  cmm.random_placement = options.random_placement;
  cmm.max_translation_mm = options.max_translation_mm;
  std::mt19937_64 rng(options.seed);
  auto measured = kinematics::MeasureWithVirtualCmm(actual_datum, cmm, rng);
  if (!measured.ok()) return measured.status();
  out.points = std::move(measured->points);
  out.points.source = actual_datum.source;
  out.truth.cmm_from_part = measured->cmm_from_part * datum_from_part;
  out.truth.plan = std::move(*plan);
  return out;
}

}  // namespace tpcal::testpieces
