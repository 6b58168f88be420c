#include "pipeline/identify_stage.h"

#include <algorithm>
#include <map>

#include "kinematics/error_state.h"
#include "testpieces/default_parameters.h"
#include "testpieces/point_association.h"

namespace tpcal::pipeline {

Result<IdentifyStageResult> RunIdentifyStage(const testpieces::TestPiece& piece,
                                             const kinematics::MachineModel& machine, const PointSet& measured,
                                             const IdentifyStageOptions& options) {
  auto inspection = gdt::EvaluatePlan(piece.inspection, measured);
  if (!inspection.ok()) return inspection.status();
  std::vector<std::string> parameters =
      options.parameters.empty() ? testpieces::DefaultParameterSet(piece, machine) : options.parameters;
  kinematics::ErrorState base(machine);
  auto active = kinematics::ActivateParameters(machine, &base, parameters);
  if (!active.ok()) return active.status();

  // Each measured point is associated with the nominal surface point at its foot (the cut that
  // made it). The datum frame built from measured features is itself off by the errors, so the
  // first pass estimates the re-alignment; the points are then re-associated in the re-aligned
  // frame (removes the second-order term e^2 / 2r of a tangential offset e on a surface of
  // radius r, ~0.05 um for 20 um on a hole) and identified again with every uncertainty.
  Rigid3 datum_from_cmm = inspection->datum_from_cmm;
  Rigid3 total_alignment = Rigid3::Identity();
  kinematics::IdentifyOptions first = options.identify;
  first.primary = kinematics::UncertaintyMethod::kAnalytic;
  first.jackknife_groups = false;
  first.monte_carlo_trials = 0;
  Result<testpieces::MeasuredObservations> obs = Status(StatusCode::kInternal, "not associated");
  Result<kinematics::IdentificationResult> id = Status(StatusCode::kInternal, "not identified");
  const bool realign = options.identify.fit_alignment;
  for (int pass = 0; pass < (realign ? 2 : 1); ++pass) {
    obs = testpieces::AssociatePoints(piece, measured, datum_from_cmm);
    if (!obs.ok()) return obs.status();
    const bool last = pass == (realign ? 1 : 0);
    id = kinematics::Identify(machine, base, *active, obs->observations, last ? options.identify : first);
    if (!id.ok()) return id.status().WithLocation(measured.source);
    total_alignment = id->alignment * total_alignment;
    if (!last) {
      // part_from_measured re-alignment A: new datum_from_cmm = datum_from_part * A * part_from_datum * old.
      datum_from_cmm = piece.part_from_datum.inverse() * id->alignment * piece.part_from_datum * datum_from_cmm;
    }
  }
  id->alignment = total_alignment;
  // Report under the names asked for (seed 002 keeps "beta_ZX" where the catalog term is
  // "E_B(0X)Z"; the ISO symbol stays beside it).
  std::map<std::string, std::string> rename;
  for (std::size_t k = 0; k < parameters.size(); ++k) {
    const std::string& coefficient = base.coefficient_info(active->coefficients[k]).name;
    if (coefficient != parameters[k]) rename[coefficient] = parameters[k];
  }
  auto renamed = [&](std::string* name) {
    if (auto it = rename.find(*name); it != rename.end()) *name = it->second;
  };
  auto renamed_text = [&](std::string* text) {
    for (const auto& [from, to] : rename)
      for (std::size_t at = text->find(from); at != std::string::npos; at = text->find(from, at + to.size()))
        text->replace(at, from.size(), to);
  };
  for (auto& p : id->parameters) renamed(&p.name);
  auto& ident = id->identifiability;
  for (auto& n : ident.not_identifiable) renamed(&n);
  for (auto* combos : {&ident.estimable, &ident.null_directions})
    for (auto& c : *combos) {
      for (auto& n : c.names) renamed(&n);
      renamed_text(&c.text);
    }
  return IdentifyStageResult{std::move(*inspection), std::move(*obs), std::move(parameters), std::move(*id)};
}

}  // namespace tpcal::pipeline
