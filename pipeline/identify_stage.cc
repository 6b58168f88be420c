#include "pipeline/identify_stage.h"

#include <algorithm>
#include <map>
#include <mutex>

#include "core/parallel.h"
#include "kinematics/error_parameters.h"
#include "kinematics/error_state.h"

namespace tpcal::pipeline {

Result<MeasuredObservations> ObservationsFromPoints(const testpieces::TestPiece& piece, const PointSet& measured,
                                                    const Rigid3& datum_from_cmm) {
  MeasuredObservations out;
  const std::size_t n = measured.size();
  // Labels and groups in file order (groups numbered by first appearance).
  std::map<int, int> group_of_label;  // PointSet feature index -> group
  std::vector<int> group(n);
  for (std::size_t i = 0; i < n; ++i) {
    const int label = measured.feature.empty() ? PointSet::kUnlabelled : measured.feature[i];
    if (label == PointSet::kUnlabelled)
      return Status(StatusCode::kInvalidArgument,
                    "point without a feature label: identification needs labelled points (segment raw scans first)",
                    measured.source, measured.LineOf(i));
    auto [it, inserted] = group_of_label.try_emplace(label, static_cast<int>(out.feature_names.size()));
    if (inserted) {
      const std::string& name = measured.feature_names[static_cast<std::size_t>(label)];
      if (!piece.Feature(name))
        return Status(StatusCode::kInvalidArgument, "feature '" + name + "' is not a feature of the " + piece.name,
                      measured.source, measured.LineOf(i));
      out.feature_names.push_back(name);
    }
    group[i] = it->second;
  }
  // The cut of every point, on all cores (each point its own slot); the first failure in file
  // order is reported.
  std::vector<const testpieces::NominalFeature*> nominal;  // per group, looked up once
  std::vector<const testpieces::FeatureCut*> cut_of;
  for (const std::string& name : out.feature_names) {
    nominal.push_back(piece.Feature(name));
    cut_of.push_back(piece.Cut(name));
  }
  out.observations.resize(n);
  out.point_index.resize(n);
  std::vector<std::size_t> first_failure;
  std::vector<Status> failure;
  std::mutex failure_mutex;
  ParallelChunks(n, 4096, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const auto g = static_cast<std::size_t>(group[i]);
      const Eigen::Vector3d p_datum = datum_from_cmm * measured.xyz_mm[i];
      auto cut = cut_of[g] ? testpieces::CutPointAtDatum(piece, *nominal[g], *cut_of[g], p_datum)
                           : testpieces::CutPointAtDatum(piece, out.feature_names[g], p_datum);  // its error
      if (!cut.ok()) {
        std::lock_guard<std::mutex> lock(failure_mutex);
        first_failure.push_back(i);
        failure.push_back(cut.status().WithLocation(measured.source, measured.LineOf(i)));
        return false;
      }
      kinematics::Observation& o = out.observations[i];
      o.cut = *cut;
      o.measured_mm = piece.part_from_datum * p_datum;
      o.group = group[i];
      out.point_index[i] = i;
    }
    return true;
  });
  if (!failure.empty()) {
    const auto k = static_cast<std::size_t>(std::min_element(first_failure.begin(), first_failure.end()) - first_failure.begin());
    return failure[k];
  }
  return out;
}

std::vector<std::string> DefaultParameterSet(const testpieces::TestPiece& piece,
                                             const kinematics::MachineModel& machine) {
  // The turning piece: seed 002's Table 2 set, plus the squareness of X to Y, which the paper
  // leaves out but every machine has: the groove S_R (and S_RI) is milled by X-Y circular
  // interpolation, so E_C(0X)Y makes it elliptic (2nd harmonic at 45 deg, gamma r / 2: 1.2 um for
  // 20 urad on S_R). Without it that ellipse was left in the gap and named an unmodelled effect.
  if (piece.kind() == testpieces::PieceKind::kTurning && machine.type == kinematics::MachineType::kAcTable) {
    std::vector<std::string> set = kinematics::Seed002Set(machine);
    set.push_back("E_C(0X)Y");
    return set;
  }
  // M2's strips are cut by X feeds at constant Z and datum on themselves: location and
  // squareness errors only tilt or shift them (absorbed by the datum), while the straightness of
  // X in Z bends them: its quadratic and cubic terms (offset and slope are the datum's).
  if (piece.kind() == testpieces::PieceKind::kFaceMillingM2 && machine.HasAxis(kinematics::Axis::kX) &&
      machine.HasAxis(kinematics::Axis::kZ))
    return {"E_ZX.c2", "E_ZX.c3"};
  return kinematics::IsoLocationSet(machine);
}

Result<IdentifyStageResult> RunIdentifyStage(const testpieces::TestPiece& piece,
                                             const kinematics::MachineModel& machine, const PointSet& measured,
                                             const IdentifyStageOptions& options) {
  auto inspection = gdt::EvaluatePlan(piece.inspection, measured);
  if (!inspection.ok()) return inspection.status();
  std::vector<std::string> parameters =
      options.parameters.empty() ? DefaultParameterSet(piece, machine) : options.parameters;
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
  Result<MeasuredObservations> obs = Status(StatusCode::kInternal, "not associated");
  Result<kinematics::IdentificationResult> id = Status(StatusCode::kInternal, "not identified");
  const bool realign = options.identify.fit_alignment;
  for (int pass = 0; pass < (realign ? 2 : 1); ++pass) {
    obs = ObservationsFromPoints(piece, measured, datum_from_cmm);
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
