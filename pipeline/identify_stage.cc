#include "pipeline/identify_stage.h"

#include <map>

#include "kinematics/error_parameters.h"
#include "kinematics/error_state.h"

namespace tpcal::pipeline {

Result<MeasuredObservations> ObservationsFromPoints(const testpieces::TestPiece& piece, const PointSet& measured,
                                                    const Rigid3& datum_from_cmm) {
  MeasuredObservations out;
  std::map<int, int> group_of_label;  // PointSet feature index -> group
  for (std::size_t i = 0; i < measured.size(); ++i) {
    const int label = measured.feature.empty() ? PointSet::kUnlabelled : measured.feature[i];
    if (label == PointSet::kUnlabelled)
      return Status(StatusCode::kInvalidArgument,
                    "point without a feature label: identification needs labelled points (segment raw scans first)",
                    measured.source, measured.LineOf(i));
    const std::string& name = measured.feature_names[static_cast<std::size_t>(label)];
    if (!piece.Feature(name))
      return Status(StatusCode::kInvalidArgument,
                    "feature '" + name + "' is not a feature of the " + piece.name, measured.source,
                    measured.LineOf(i));
    auto [it, inserted] = group_of_label.try_emplace(label, static_cast<int>(out.feature_names.size()));
    if (inserted) out.feature_names.push_back(name);
    const Eigen::Vector3d p_datum = datum_from_cmm * measured.xyz_mm[i];
    auto cut = testpieces::CutPointAtDatum(piece, name, p_datum);
    if (!cut.ok()) return cut.status().WithLocation(measured.source, measured.LineOf(i));
    kinematics::Observation o;
    o.cut = *cut;
    o.measured_mm = piece.part_from_datum * p_datum;
    o.group = it->second;
    out.observations.push_back(o);
    out.point_index.push_back(i);
  }
  return out;
}

std::vector<std::string> DefaultParameterSet(const testpieces::TestPiece& piece,
                                             const kinematics::MachineModel& machine) {
  if (piece.kind() == testpieces::PieceKind::kTurning && machine.type == kinematics::MachineType::kAcTable)
    return kinematics::Seed002Set(machine);
  return kinematics::IsoLocationSet(machine);
}

Result<IdentifyStageResult> RunIdentifyStage(const testpieces::TestPiece& piece,
                                             const kinematics::MachineModel& machine, const PointSet& measured,
                                             const IdentifyStageOptions& options) {
  auto inspection = gdt::EvaluatePlan(piece.inspection, measured);
  if (!inspection.ok()) return inspection.status();
  auto obs = ObservationsFromPoints(piece, measured, inspection->datum_from_cmm);
  if (!obs.ok()) return obs.status();

  std::vector<std::string> parameters =
      options.parameters.empty() ? DefaultParameterSet(piece, machine) : options.parameters;
  kinematics::ErrorState base(machine);
  for (const auto& name : parameters) {
    if (Status s = base.SetParameter(machine, name, 0.0); !s.ok()) return s;
  }
  auto active = kinematics::SelectCoefficients(base, parameters);
  if (!active.ok()) return active.status();
  auto id = kinematics::Identify(machine, base, *active, obs->observations, options.identify);
  if (!id.ok()) return id.status().WithLocation(measured.source);
  return IdentifyStageResult{std::move(*inspection), std::move(*obs), std::move(parameters), std::move(*id)};
}

}  // namespace tpcal::pipeline
