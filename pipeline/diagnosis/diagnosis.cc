#include "pipeline/diagnosis/diagnosis.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include "gdt/inspection.h"
#include "kinematics/slot_linearisation.h"
#include "pipeline/diagnosis/diagnosis_base_fit.h"
#include "pipeline/diagnosis/diagnosis_candidates.h"
#include "pipeline/diagnosis/diagnosis_gap_summary.h"
#include "pipeline/diagnosis/diagnosis_reference_match.h"
#include "pipeline/diagnosis/diagnosis_screening.h"
#include "pipeline/diagnosis/diagnosis_scoring.h"
#include "pipeline/diagnosis/diagnosis_verdict.h"
#include "testpieces/default_parameters.h"
#include "testpieces/point_association.h"

namespace tpcal::pipeline {

Status DiagnosisOptions::Validate() const {
  if (!(alpha > 0 && alpha < 1)) return {StatusCode::kInvalidArgument, "diagnosis alpha must be in (0, 1)"};
  if (!(absorbed_tolerance > 0 && absorbed_tolerance < 1))
    return {StatusCode::kInvalidArgument, "diagnosis absorbed_tolerance must be in (0, 1)"};
  if (!(noise_um >= 0)) return {StatusCode::kInvalidArgument, "diagnosis noise_um must be >= 0"};
  if (!(alias_capture > 0 && alias_capture <= 1))
    return {StatusCode::kInvalidArgument, "diagnosis alias_capture must be in (0, 1]"};
  if (max_harmonic < 1) return {StatusCode::kInvalidArgument, "diagnosis max_harmonic must be >= 1"};
  if (!(stand_out_z > 0)) return {StatusCode::kInvalidArgument, "diagnosis stand_out_z must be > 0"};
  if (!(holdout_tolerance > 0 && holdout_tolerance < 1))
    return {StatusCode::kInvalidArgument, "diagnosis holdout_tolerance must be in (0, 1)"};
  if (!(reference_match_mm > 0)) return {StatusCode::kInvalidArgument, "diagnosis reference_match_mm must be > 0"};
  if (!(reference_nuisance_ratio > 0))
    return {StatusCode::kInvalidArgument, "diagnosis reference_nuisance_ratio must be > 0"};
  if (reference_uncertainty && !reference)
    return {StatusCode::kInvalidArgument, "diagnosis reference_uncertainty needs a reference"};
  return {};
}

std::vector<std::string> SameFamilyAlternatives(const DiagnosisResult& result) {
  std::vector<std::string> out;
  for (const std::string& name : result.verdict.indistinguishable_candidates)
    for (const CandidateResult& c : result.candidates)
      if (c.name == name && c.family == result.verdict.family) {
        out.push_back(name);
        break;
      }
  return out;
}

namespace {

// What every step of one diagnosis shares: the piece and machine, every observation, the point
// reference's normal deviations (per observation, or null), the base parameters, the base fitted
// to every observation, and the candidate catalogue on them, built once when first asked for
// (the diagnosis of every point and each screen run again with an effect ask for the same one).
class WholeInput {
 public:
  WholeInput(const testpieces::TestPiece& piece, const kinematics::MachineModel& machine,
             const testpieces::MeasuredObservations& mo, const Eigen::VectorXd* reference_dev_um,
             const std::vector<std::string>& base_names, bool reference_mode, const diagnosis_internal::BaseFit& fit)
      : piece(piece), machine(machine), mo(mo), reference_dev_um(reference_dev_um), base_names(base_names),
        reference_mode(reference_mode), fit(fit) {}

  // BuildCandidates on every observation and `fit` (its error, if it failed).
  Result<const CandidateCatalogue*> Catalogue() const {
    if (!catalogue_)
      catalogue_.emplace(BuildCandidates(piece, machine, fit.errors, mo, base_names, reference_mode, fit.design.get()));
    if (!catalogue_->ok()) return catalogue_->status();
    return &**catalogue_;
  }

  const testpieces::TestPiece& piece;
  const kinematics::MachineModel& machine;
  const testpieces::MeasuredObservations& mo;
  const Eigen::VectorXd* reference_dev_um;
  const std::vector<std::string>& base_names;
  const bool reference_mode;
  const diagnosis_internal::BaseFit& fit;

 private:
  mutable std::optional<Result<CandidateCatalogue>> catalogue_;
};

// Steps 1-4 of the diagnosis (diagnosis.h) on observations already screened, `fit` and
// `catalogue` on them: the base model and its gap, every candidate scored against it, the
// verdict, where the gap lies.
void DiagnoseScreened(const kinematics::MachineModel& machine, const testpieces::MeasuredObservations& mo,
                      const DiagnosisOptions& options, bool point_reference, bool reference_mode,
                      const diagnosis_internal::BaseFit& fit, const CandidateCatalogue& catalogue, DiagnosisResult* out) {
  namespace step = diagnosis_internal;
  step::DescribeBaseModel(fit, options, point_reference, reference_mode, out);
  const step::BaseGap gap = step::MakeBaseGap(fit, mo, options.holdout_tolerance);
  step::ReportBaseGap(gap, mo, out);

  const step::ScoredCandidates scored = step::ScoreCandidates(catalogue, fit, gap, out->base_parameters, options);

  const step::VerdictInputs in{catalogue, scored, fit, gap, options, {}};
  const step::Ranking ranking = step::RankCandidates(scored);
  const step::FinalModel final_model = step::DecideVerdict(in, ranking, out);
  step::ReportCandidates(in, ranking, final_model.verdict, out);

  const Eigen::Index n = gap.r.size();
  out->noise_sigma_um = options.noise_um > 0
                            ? options.noise_um
                            : std::sqrt(std::max(0.0, final_model.ssr - final_model.reference_ss) /
                                        std::max<double>(1.0, static_cast<double>(n - final_model.dof)) /
                                        gap.mean_noise_scale2);
  step::SummariseGap(machine, mo, gap.r, out->noise_sigma_um, options, out, fit.reference_remaining_um);
  step::CompleteVerdict(in, out);
}

// Steps 1-4 on the observations `screened` keeps: the base refitted without the flagged points
// and its catalogue (or the whole's when nothing is left out), then DiagnoseScreened.
Result<DiagnosisResult> DiagnoseKept(const WholeInput& whole, const DiagnosisOptions& options,
                                     const diagnosis_internal::ScreenedInput& screened) {
  namespace step = diagnosis_internal;
  const bool point_reference = whole.reference_dev_um != nullptr;
  DiagnosisResult out;
  step::ReportScreen(screened, whole.mo, &out);
  if (!screened.left_out) {
    auto catalogue = whole.Catalogue();
    if (!catalogue.ok()) return catalogue.status();
    DiagnoseScreened(whole.machine, whole.mo, options, point_reference, whole.reference_mode, whole.fit, **catalogue,
                     &out);
    return out;
  }
  auto fit = step::FitBaseModel(whole.piece, whole.machine, screened.observations.observations, screened.options,
                                whole.base_names, whole.reference_mode,
                                point_reference ? &screened.reference_dev_um : nullptr);
  if (!fit.ok()) return fit.status();
  auto catalogue = BuildCandidates(whole.piece, whole.machine, fit->errors, screened.observations, whole.base_names,
                                   whole.reference_mode, fit->design.get());
  if (!catalogue.ok()) return catalogue.status();
  DiagnoseScreened(whole.machine, screened.observations, screened.options, point_reference, whole.reference_mode, *fit,
                   *catalogue, &out);
  return out;
}

// The columns on every observation of the candidate named `name`, or nullopt.
std::optional<Eigen::MatrixXd> CandidateMatrix(const CandidateCatalogue& all, const std::string& name) {
  for (const auto& c : all.candidates) {
    if (c.name != name) continue;
    Eigen::MatrixXd m(c.col(0).size(), c.cols());
    for (Eigen::Index j = 0; j < c.cols(); ++j) m.col(j) = c.col(j);
    return m;
  }
  return std::nullopt;
}

// The columns of the effect the verdict names: its candidate's, and the pair's second candidate's
// when the verdict names that family too (nullopt: the verdict's candidate is not in `all`).
std::optional<Eigen::MatrixXd> VerdictColumns(const CandidateCatalogue& all, const DiagnosisResult& d) {
  auto leading = CandidateMatrix(all, d.verdict.name);
  const bool pair = d.verdict.also && d.pair && d.pair->names.size() == 2 && d.pair->families[1] == *d.verdict.also;
  if (!leading || !pair) return leading;
  const auto second = CandidateMatrix(all, d.pair->names[1]);
  if (!second) return leading;
  Eigen::MatrixXd both(leading->rows(), leading->cols() + second->cols());
  both << *leading, *second;
  return both;
}

// Whether local defects depart on both sides of the model (one peak > 0, another < 0): a burr, a
// chip or a dent departs one way; the part of an effect the base leaves on one feature swings both.
bool PatchesOnBothSides(const std::vector<LocalDefect>& patches) {
  return std::any_of(patches.begin(), patches.end(), [](const LocalDefect& p) { return p.peak_um > 0; }) &&
         std::any_of(patches.begin(), patches.end(), [](const LocalDefect& p) { return p.peak_um < 0; });
}

// What the screen flagged that an effect may explain: its patches, or every flag (outliers too).
enum class Flagged { kPatches, kEveryFlag };

// The diagnosis of every point (the screen off): when it names an effect of the catalogue (a pair
// if `needs_pair`) whose model (both of a pair) leaves no patch (kEveryFlag: no point) to flag,
// the screen run again with that effect modelled, the diagnosis of what that screen keeps, if its
// verdict is the whole diagnosis's; for kPatches with local_defect named indistinguishable and
// `first`'s patches as explained_patches. Else nullopt.
std::optional<DiagnosisResult> FlagsExplained(const WholeInput& whole, const DiagnosisOptions& options,
                                              const DiagnosisResult& first, bool needs_pair, Flagged flagged) {
  namespace step = diagnosis_internal;
  DiagnosisOptions keep = options;
  keep.screen_outliers = false;
  const step::ScreenedInput kept = step::ScreenBaseFit(whole.fit, whole.mo, keep, whole.reference_dev_um);
  auto every = DiagnoseKept(whole, keep, kept);
  if (!every.ok() || !IsCatalogueFamily(every->verdict.family) || (needs_pair && !every->verdict.also))
    return std::nullopt;
  auto all = whole.Catalogue();
  if (!all.ok()) return std::nullopt;
  const auto effect = VerdictColumns(**all, *every);
  if (!effect) return std::nullopt;
  const step::ScreenedInput again = step::ScreenBaseFit(whole.fit, whole.mo, options, whole.reference_dev_um, &*effect);
  if (!again.screen.patches.empty() || (flagged == Flagged::kEveryFlag && again.screen.CountFlagged() > 0))
    return std::nullopt;
  auto d = DiagnoseKept(whole, options, again);
  if (!d.ok() || d->verdict.family != every->verdict.family) return std::nullopt;
  if (flagged == Flagged::kEveryFlag) return std::move(*d);
  auto& alike = d->verdict.indistinguishable_from;
  alike.push_back("local_defect");
  std::sort(alike.begin(), alike.end());
  d->explained_patches = first.local_defects;
  return std::move(*d);
}

// When the screen's patches made the verdict local_defect and they lie on both sides of the
// model (PatchesOnBothSides): the diagnosis of every point, and if it names an effect of the
// catalogue whose model leaves no patch to flag, that effect explains the patches
// (FlagsExplained). Else `first`: also when the screen leaves nothing out (--keep-outliers).
Result<DiagnosisResult> PatchAsEffect(const WholeInput& whole, const DiagnosisOptions& options, DiagnosisResult first) {
  if (!options.screen_outliers || !PatchesOnBothSides(first.local_defects)) return first;
  auto d = FlagsExplained(whole, options, first, false, Flagged::kPatches);
  return d ? std::move(*d) : std::move(first);
}

// When the verdict names one effect of the catalogue beside local defects: a second effect the
// verdict's model leaves on a few features is flagged as patches, and leaving them out takes its
// evidence away. If the diagnosis of every point names a pair whose model leaves no patch to flag,
// the pair explains the patches (FlagsExplained). Else `first`.
Result<DiagnosisResult> PatchAsSecondEffect(const WholeInput& whole, const DiagnosisOptions& options,
                                            DiagnosisResult first) {
  if (!options.screen_outliers || first.local_defects.empty() || !IsCatalogueFamily(first.verdict.family) ||
      first.verdict.also)
    return first;
  auto d = FlagsExplained(whole, options, first, true, Flagged::kPatches);
  return d && d->verdict.also ? std::move(*d) : std::move(first);
}

// When the verdict is none with points left out: an effect whose signature peaks on a few points
// (a Z drift of the table on one point of each of four shoulder faces, 5-6 um beside 0.5 um of
// noise) is flagged there point by point, and leaving them out takes its evidence away. If the
// diagnosis of every point names an effect of the catalogue whose model leaves no point to flag,
// that effect explains them (FlagsExplained). Else `first`.
Result<DiagnosisResult> FlagsAsEffect(const WholeInput& whole, const DiagnosisOptions& options, DiagnosisResult first) {
  if (!options.screen_outliers || first.verdict.family != "none" || first.outliers.empty()) return first;
  auto d = FlagsExplained(whole, options, first, false, Flagged::kEveryFlag);
  return d ? std::move(*d) : std::move(first);
}

// The diagnosis (diagnosis.h): the base fitted to every point, the outlier screen, then the
// diagnosis of the points it keeps. When points were left out and the verdict is an effect of
// the catalogue, the screen is run again with that effect in the model (with both of a pair the
// verdict names: a servo glitch beside a drift is an outlier to the drift alone; on a piece of
// 8-point circles a 3-lobe error motion looks point by point like isolated faults; only the model
// of the whole piece tells): if it flags other points, the diagnosis is made again on what it keeps.
// A verdict of one effect beside local defects then gets PatchAsSecondEffect's check; a verdict
// of local defects PatchAsEffect's, and none with points left out FlagsAsEffect's.
// `reference_dev_um` (per observation, or null): the point reference's normal deviations,
// subtracted from the measured ones (DiagnoseAgainstPoints).
Result<DiagnosisResult> DiagnoseImpl(const testpieces::TestPiece& piece, const kinematics::MachineModel& machine,
                                     const testpieces::MeasuredObservations& mo, const DiagnosisOptions& given,
                                     const Eigen::VectorXd* reference_dev_um) {
  namespace step = diagnosis_internal;
  TPCAL_RETURN_IF_ERROR(given.Validate());
  TPCAL_RETURN_IF_ERROR(given.screen.Validate());
  DiagnosisOptions options = given;  // with the neighbour graph of mo, made once for every screen
  const int k = options.screen.neighbours;
  if (!options.neighbour_graph || !options.neighbour_graph->Fits(mo.observations.size(), k))
    options.neighbour_graph =
        std::make_shared<const FeatureNeighbourGraph>(FeatureNeighbourGraph{k, FeatureNeighbours(mo.observations, k)});
  const bool point_reference = reference_dev_um != nullptr;
  if (point_reference && options.reference)
    return Status(StatusCode::kInvalidArgument, "diagnosis: a reference point file and reference machine errors together");
  const bool reference_mode = options.reference.has_value() || point_reference;
  std::vector<std::string> base_names =
      options.base_parameters.empty() ? testpieces::DefaultParameterSet(piece, machine) : options.base_parameters;
  auto fit =
      step::FitBaseModel(piece, machine, mo.observations, options, base_names, reference_mode, reference_dev_um);
  if (!fit.ok()) return fit.status();
  const WholeInput whole(piece, machine, mo, reference_dev_um, base_names, reference_mode, *fit);
  const step::ScreenedInput screened = step::ScreenBaseFit(*fit, mo, options, reference_dev_um);
  auto first = DiagnoseKept(whole, options, screened);
  if (first.ok() && first->verdict.family == "local_defect") return PatchAsEffect(whole, options, std::move(*first));
  if (first.ok() && first->verdict.family == "none") return FlagsAsEffect(whole, options, std::move(*first));
  if (!first.ok() || !screened.left_out || !IsCatalogueFamily(first->verdict.family)) return first;
  auto all = whole.Catalogue();
  if (!all.ok()) return all.status();
  const auto effect = VerdictColumns(**all, *first);
  if (!effect) return first;
  const step::ScreenedInput again = step::ScreenBaseFit(*fit, mo, options, reference_dev_um, &*effect);
  if (again.screen.flag == screened.screen.flag) return PatchAsSecondEffect(whole, options, std::move(*first));
  auto second = DiagnoseKept(whole, options, again);
  if (!second.ok()) return second;
  return PatchAsSecondEffect(whole, options, std::move(*second));
}

// Labelled points of `points` (any placement) as observations in the nominal part frame (datum
// frame from the piece's inspection plan). Points no cut of their feature reaches are skipped
// ("file:line: why" in *skipped); unlabelled points and unknown features stay errors.
Result<testpieces::MeasuredObservations> ObservationsForDiagnosis(const testpieces::TestPiece& piece, const PointSet& points,
                                                      std::vector<std::string>* skipped) {
  auto inspection = gdt::EvaluatePlan(piece.inspection, points);
  if (!inspection.ok()) return inspection.status();
  // A point whose cut cannot be found (typically at a face edge, pushed out of the machined band
  // by errors and noise) is left out and reported; unknown features and unlabelled points stay errors.
  return testpieces::AssociatePoints(piece, points, inspection->datum_from_cmm, testpieces::UnreachedPoint::kSkip,
                                     skipped);
}

}  // namespace

void AttachSourceLines(const PointSet& measured, DiagnosisResult* result) {
  AttachScreenLines(measured, &result->outliers, &result->local_defects);
  std::vector<ScreenedPoint> none;
  AttachScreenLines(measured, &none, &result->explained_patches);
}

bool IsCatalogueFamily(const std::string& family) {
  return family != "none" && family != "local_defect" && family != "unexplained";
}

Result<std::vector<kinematics::ErrorSlot>> NominalDiagnosisSlots(const testpieces::TestPiece& piece,
                                                                 const kinematics::MachineModel& machine,
                                                                 const DiagnosisOptions& options) {
  // As DiagnoseImpl's first linearisation (not in reference mode).
  const std::vector<std::string> base_names =
      options.base_parameters.empty() ? testpieces::DefaultParameterSet(piece, machine) : options.base_parameters;
  kinematics::ErrorState errors(machine);
  kinematics::ActiveSet active;
  if (!base_names.empty()) {
    auto act = kinematics::ActivateParameters(machine, &errors, base_names);
    if (!act.ok()) return act.status();
    active = *act;
  }
  auto candidate_slots = CandidateSlots(piece, machine, errors, base_names, /*reference_mode=*/false);
  if (!candidate_slots.ok()) return candidate_slots.status();
  return diagnosis_internal::DiagnosisSlotUnion(errors, active.coefficients, *candidate_slots);
}

Result<DiagnosisResult> DiagnoseObservations(const testpieces::TestPiece& piece,
                                             const kinematics::MachineModel& machine,
                                             const testpieces::MeasuredObservations& observations, const DiagnosisOptions& options) {
  return DiagnoseImpl(piece, machine, observations, options, nullptr);
}

Result<DiagnosisResult> Diagnose(const testpieces::TestPiece& piece, const kinematics::MachineModel& machine,
                                 const PointSet& measured, const DiagnosisOptions& options) {
  std::vector<std::string> skipped;
  auto obs = ObservationsForDiagnosis(piece, measured, &skipped);
  if (!obs.ok()) return obs.status();
  auto result = DiagnoseImpl(piece, machine, *obs, options, nullptr);
  if (!result.ok()) return result;
  result->skipped_points = std::move(skipped);
  AttachSourceLines(measured, &*result);
  return result;
}

Result<DiagnosisResult> DiagnoseAgainstPoints(const testpieces::TestPiece& piece, const kinematics::MachineModel& machine,
                                              const PointSet& measured, const PointSet& reference,
                                              const DiagnosisOptions& options) {
  namespace step = diagnosis_internal;
  TPCAL_RETURN_IF_ERROR(options.Validate());
  if (options.reference)
    return Status(StatusCode::kInvalidArgument, "diagnosis: a reference point file and reference machine errors together");
  std::vector<std::string> skipped, skipped_ref;
  auto mo = ObservationsForDiagnosis(piece, measured, &skipped);
  if (!mo.ok()) return mo.status();
  auto ro = ObservationsForDiagnosis(piece, reference, &skipped_ref);
  if (!ro.ok()) return ro.status();
  // The reference's normal deviations at nominal errors, as DiagnoseImpl computes the measured ones.
  auto lin = kinematics::LineariseBySlots(machine, kinematics::ErrorState(machine), {}, ro->observations);
  if (!lin.ok()) return lin.status();
  const Eigen::VectorXd ref_dev_um = lin->measured_dev_um - lin->predicted_dev_um;
  const double tol_mm = options.reference_match_mm;
  step::ReferenceMatching matching = step::MatchReferencePoints(*mo, *ro, tol_mm);
  std::vector<double> dev;
  const testpieces::MeasuredObservations kept =
      step::KeepMatched(*mo, measured, ref_dev_um, tol_mm, &matching, &dev, &skipped);
  const Eigen::VectorXd dev_um = Eigen::Map<const Eigen::VectorXd>(dev.data(), static_cast<Eigen::Index>(dev.size()));
  auto result = DiagnoseImpl(piece, machine, kept, options, &dev_um);
  if (!result.ok()) return result.status();
  for (auto& s : skipped_ref) skipped.push_back("reference: " + s);
  result->skipped_points = std::move(skipped);
  result->reference_match = matching.summary;
  AttachSourceLines(measured, &*result);
  return result;
}

}  // namespace tpcal::pipeline
