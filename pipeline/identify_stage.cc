#include "pipeline/identify_stage.h"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <utility>

#include "kinematics/error_state.h"
#include "kinematics/slot_linearisation.h"
#include "pipeline/diagnosis/diagnosis.h"
#include "pipeline/diagnosis/outlier_screen.h"
#include "testpieces/default_parameters.h"
#include "testpieces/point_association.h"

namespace tpcal::pipeline {
namespace {

struct Associated {
  testpieces::MeasuredObservations observations;
  std::optional<ScanCellSummary> scan_cells;
  std::vector<ScreenedPoint> flagged_hits;  // single hits the scan cells flagged
};

// The hits a dense scan's cells flagged, as the outlier screen lists its points.
std::vector<ScreenedPoint> FlaggedHitsListed(const ScanCells& cells, const testpieces::MeasuredObservations& per_point) {
  std::vector<ScreenedPoint> out;
  for (const FlaggedHit& h : cells.flagged_hits) {
    const std::string& feature =
        per_point.feature_names[static_cast<std::size_t>(per_point.observations[h.observation].group)];
    out.push_back({h.point_index, 0, feature, "outlier", h.departure_um,
                   fmt::format("outlier: {:.2f} um from the fit through the other {} hits of its scan cell on {} ({:.1f} "
                               "sigma, beyond {:.1f}; one hit's noise {:.2f} um)",
                               h.departure_um, h.cell_hits - 1, feature, std::abs(h.z), cells.hit_outlier_z,
                               cells.hit_sigma_um),
                   cells.hits_left_out});
  }
  return out;
}

// Points to observations in the datum frame `datum_from_cmm`, pooled into scan-line cells when
// the file is dense.
Result<Associated> Associate(const testpieces::TestPiece& piece, const PointSet& measured, const Rigid3& datum_from_cmm,
                             const IdentifyStageOptions& options, bool announce) {
  if (announce && options.on_step) options.on_step("associate");
  auto obs = testpieces::AssociatePoints(piece, measured, datum_from_cmm);
  if (!obs.ok()) return obs.status();
  Associated out{std::move(*obs), std::nullopt, {}};
  const std::size_t n = out.observations.observations.size();
  ScanCellOptions cells_options = options.scan_cells;
  if (cells_options.above_points == 0 || n <= cells_options.above_points) return out;
  if (cells_options.hit_outlier_z == 0) cells_options.hit_outlier_z = SeedZFor(options.screen, n);
  cells_options.leave_out_flagged_hits = options.screen_outliers;
  if (announce && options.on_step) options.on_step("scan cells");
  auto cells = ReduceToScanCells(out.observations, cells_options);
  if (!cells.ok()) return cells.status();
  if (*cells) {
    out.scan_cells = Summarise(**cells);
    out.flagged_hits = FlaggedHitsListed(**cells, out.observations);
    out.observations = std::move((*cells)->observations);
  }
  return out;
}

// A dense file's first pass only estimates the re-alignment, which the final pass fits again. On
// the pipeline_bench scan (2e6 points, 1 um noise) an even sample of 2e4 points leaves 0.04 um and
// 0.06 urad for the final pass to fit, and the results move by at most 0.08 u: no more than a
// 10 nm shift of the frame moves them through the scan cells' boundaries (0.14 u). Each feature
// keeps at least kFirstPassPerFeature points (or all it has), so no feature's datum drops out.
constexpr std::size_t kFirstPassPerFeature = 500;

// The sample of about `target` points: positions, normals, labels and lines (all the association
// reads).
PointSet FirstPassSample(const PointSet& all, std::size_t target) {
  const std::size_t stride = std::max<std::size_t>(1, all.size() / target);
  auto slot = [&](std::size_t i) { return static_cast<std::size_t>((all.feature.empty() ? -1 : all.feature[i]) + 1); };
  std::vector<std::size_t> count(all.feature_names.size() + 1, 0), seen(count.size(), 0);
  for (std::size_t i = 0; i < all.size(); ++i) ++count[slot(i)];
  PointSet out;
  out.source = all.source;
  out.feature_names = all.feature_names;
  for (std::size_t i = 0; i < all.size(); ++i) {
    const std::size_t f = slot(i);
    const std::size_t every = std::clamp<std::size_t>(count[f] / kFirstPassPerFeature, 1, stride);
    if (seen[f]++ % every != 0) continue;
    out.xyz_mm.push_back(all.xyz_mm[i]);
    if (all.has_normals()) out.normal.push_back(all.normal[i]);
    if (!all.feature.empty()) out.feature.push_back(all.feature[i]);
    if (!all.line.empty()) out.line.push_back(all.line[i]);
  }
  return out;
}

// One slot linearisation at the nominal machine for the base set and every diagnosis candidate:
// the identification's first design (by the chain rule to its coefficients) and the diagnosis's,
// one pass over the observations for both.
Result<std::shared_ptr<const kinematics::SlotDesign>> NominalSlotDesign(const testpieces::TestPiece& piece,
                                                                        const kinematics::MachineModel& machine,
                                                                        const kinematics::ErrorState& base,
                                                                        const kinematics::ActiveSet& active,
                                                                        const std::vector<std::string>& parameters,
                                                                        const testpieces::MeasuredObservations& obs,
                                                                        kinematics::IdentifyOptions* identify) {
  DiagnosisOptions diagnosis;
  diagnosis.base_parameters = parameters;
  auto slots = NominalDiagnosisSlots(piece, machine, diagnosis);
  if (!slots.ok()) return slots.status();
  kinematics::AddSlots(kinematics::SlotsOf(base, active.coefficients), &*slots);
  auto shared = kinematics::LineariseSlots(machine, base, *slots, obs.observations);
  if (!shared.ok()) return shared.status();
  auto J = kinematics::CoefficientColumns(*shared, base, active.coefficients, obs.observations);
  if (!J.ok()) return J.status();
  auto lin0 = std::make_shared<kinematics::LinearDesign>();
  lin0->J_dev_params = std::move(*J);
  lin0->J_dev_alignment = shared->lin.J_dev_alignment;
  lin0->measured_dev_um = shared->lin.measured_dev_um;
  lin0->predicted_dev_um = shared->lin.predicted_dev_um;
  identify->initial_design = std::move(lin0);
  return std::make_shared<const kinematics::SlotDesign>(std::move(*shared));
}

// The outlier screen on the final pass's nominal design (base columns and, when fitted, the
// re-alignment): flagged points are listed in `out`, and unless options.screen_outliers is off
// left out of the observations, the initial design and the shared slot design.
struct ScreenListing {
  std::vector<ScreenedPoint> outliers;
  std::vector<LocalDefect> local_defects;
  double neighbour_sigma_um = 0.0;
  double neighbour_sigma_dof = 0.0;
  std::optional<testpieces::MeasuredObservations> unscreened;
  std::shared_ptr<const kinematics::SlotDesign> unscreened_slots;
  std::shared_ptr<const FeatureNeighbourGraph> neighbours;
};

void ScreenFinalPass(const IdentifyStageOptions& options, const PointSet& measured, testpieces::MeasuredObservations* obs,
                     kinematics::IdentifyOptions* pass_options, std::shared_ptr<const kinematics::SlotDesign>* slots,
                     ScreenListing* out) {
  const kinematics::LinearDesign& lin = *pass_options->initial_design;
  const Eigen::Index q = lin.J_dev_params.cols(), a = options.identify.fit_alignment ? 6 : 0;
  Eigen::MatrixXd X(lin.J_dev_params.rows(), q + a);
  X.leftCols(q) = lin.J_dev_params;
  if (a > 0) X.rightCols(a) = lin.J_dev_alignment;
  const OutlierScreen screen = ScreenOutliers(X, lin.measured_dev_um - lin.predicted_dev_um, obs->observations, options.screen);
  const bool left_out = options.screen_outliers && screen.CountFlagged() > 0;
  out->neighbour_sigma_um = screen.sigma_um;
  out->neighbour_sigma_dof = screen.sigma_dof;
  out->neighbours = screen.neighbours;
  ListFlagged(screen, *obs, left_out, &out->outliers, &out->local_defects);
  AttachScreenLines(measured, &out->outliers, &out->local_defects);
  if (!left_out) return;
  out->unscreened = *obs;
  out->unscreened_slots = *slots;
  const std::vector<int> rows = screen.KeptIndices();
  *obs = ObservationRows(*obs, rows);
  pass_options->initial_design = std::make_shared<kinematics::LinearDesign>(kinematics::RowsOf(lin, rows));
  *slots = std::make_shared<const kinematics::SlotDesign>(kinematics::RowsOf(**slots, rows));
}

// Reports the parameters under the names asked for (seed 002 keeps "beta_ZX" where the catalog
// term is "E_B(0X)Z"; the ISO symbol stays beside it).
void NameAsAsked(const kinematics::ErrorState& base, const kinematics::ActiveSet& active,
                 const std::vector<std::string>& parameters, kinematics::IdentificationResult* id) {
  std::map<std::string, std::string> rename;
  for (std::size_t k = 0; k < parameters.size(); ++k) {
    const std::string& coefficient = base.coefficient_info(active.coefficients[k]).name;
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
}

}  // namespace

kinematics::IdentifyOptions IdentifyOptionsFor(const std::string& uncertainty, int mc_trials, int subset_trials,
                                               std::uint64_t seed) {
  kinematics::IdentifyOptions o;
  o.seed = seed;
  if (uncertainty == "analytic") {
    o.primary = kinematics::UncertaintyMethod::kAnalytic;
    o.jackknife_groups = false;
  } else if (uncertainty == "mc") {
    o.primary = kinematics::UncertaintyMethod::kMonteCarlo;
    o.monte_carlo_trials = mc_trials;
    o.jackknife_groups = false;
  } else if (uncertainty == "jackknife") {
    o.primary = kinematics::UncertaintyMethod::kJackknifePoints;
  } else {  // all
    o.primary = kinematics::UncertaintyMethod::kJackknifePoints;
    o.monte_carlo_trials = mc_trials;
  }
  o.random_subset_trials = subset_trials;
  return o;
}

Result<IdentifyStageResult> RunIdentifyStage(const testpieces::TestPiece& piece,
                                             const kinematics::MachineModel& machine, const PointSet& measured,
                                             const IdentifyStageOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.scan_cells.Validate());
  std::vector<std::string> parameters =
      options.parameters.empty() ? testpieces::DefaultParameterSet(piece, machine) : options.parameters;
  kinematics::ErrorState base(machine);
  auto active = kinematics::ActivateParameters(machine, &base, parameters);
  if (!active.ok())
    return options.parameters.empty() ? active.status() : active.status().WithLocation(options.parameters_origin);
  if (options.on_step) options.on_step("gdt");
  auto inspection = gdt::EvaluatePlan(piece.inspection, measured);
  if (!inspection.ok()) return inspection.status();

  // Each measured point is associated with the nominal surface point at its foot (the cut that
  // made it). The datum frame built from measured features is itself off by the errors, so the
  // first pass estimates the re-alignment (a dense file's on a sample); the points are then
  // re-associated in the re-aligned frame (removes the second-order term e^2 / 2r of a
  // tangential offset e on a surface of radius r, ~0.05 um for 20 um on a hole) and identified
  // again with every uncertainty.
  Rigid3 datum_from_cmm = inspection->datum_from_cmm;
  Rigid3 total_alignment = Rigid3::Identity();
  kinematics::IdentifyOptions first = options.identify;
  first.primary = kinematics::UncertaintyMethod::kAnalytic;
  first.jackknife_groups = false;
  first.monte_carlo_trials = 0;
  Result<Associated> obs = Status(StatusCode::kInternal, "not associated");
  Result<kinematics::IdentificationResult> id = Status(StatusCode::kInternal, "not identified");
  std::shared_ptr<const kinematics::SlotDesign> slot_design;
  ScreenListing screened;
  const bool realign = options.identify.fit_alignment;
  const ScanCellOptions& cells = options.scan_cells;
  const bool dense = cells.above_points > 0 && measured.size() > cells.above_points;
  const std::optional<PointSet> first_sample = realign && dense && options.first_pass_points > 0
                                                   ? std::optional(FirstPassSample(measured, options.first_pass_points))
                                                   : std::nullopt;
  for (int pass = 0; pass < (realign ? 2 : 1); ++pass) {
    const bool sampled = pass == 0 && first_sample;
    obs = Associate(piece, sampled ? *first_sample : measured, datum_from_cmm, options, pass == 0);
    if (!obs.ok() && sampled) obs = Associate(piece, measured, datum_from_cmm, options, false);  // the file's first error
    if (!obs.ok()) return obs.status();
    if (pass == 0 && options.on_step) options.on_step("identify");
    const bool last = pass == (realign ? 1 : 0);
    kinematics::IdentifyOptions pass_options = last ? options.identify : first;
    if (last) {
      auto design = NominalSlotDesign(piece, machine, base, *active, parameters, obs->observations, &pass_options);
      if (!design.ok()) return design.status().WithLocation(measured.source);
      slot_design = std::move(*design);
      std::vector<LocalDefect> no_patches;
      AttachScreenLines(measured, &obs->flagged_hits, &no_patches);
      screened.outliers = obs->flagged_hits;
      ScreenFinalPass(options, measured, &obs->observations, &pass_options, &slot_design, &screened);
    }
    id = kinematics::Identify(machine, base, *active, obs->observations.observations, pass_options);
    if (!id.ok()) return id.status().WithLocation(measured.source);
    total_alignment = id->alignment * total_alignment;
    if (!last) {
      // part_from_measured re-alignment A: new datum_from_cmm = datum_from_part * A * part_from_datum * old.
      datum_from_cmm = piece.part_from_datum.inverse() * id->alignment * piece.part_from_datum * datum_from_cmm;
    }
  }
  id->alignment = total_alignment;
  NameAsAsked(base, *active, parameters, &*id);
  return IdentifyStageResult{std::move(*inspection),       std::move(obs->observations),
                             std::move(parameters),        std::move(*id),
                             obs->scan_cells,              std::move(slot_design),
                             std::move(screened.outliers), std::move(screened.local_defects),
                             screened.neighbour_sigma_um,  screened.neighbour_sigma_dof,
                             std::move(screened.unscreened), std::move(screened.unscreened_slots),
                             std::move(screened.neighbours),  std::move(obs->flagged_hits)};
}

}  // namespace tpcal::pipeline
