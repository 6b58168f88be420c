#include "pipeline/diagnosis/diagnosis_base_fit.h"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "kinematics/errors_yaml.h"
#include "pipeline/diagnosis/diagnosis_candidates.h"
#include "pipeline/diagnosis/diagnosis_reference_nuisance.h"

namespace tpcal::pipeline::diagnosis_internal {
namespace {

// Numerical rank: the base model absorbs every direction it can fit, however weakly (identification
// reports directions below 1e-3 of the strongest as not identifiable, kinematics/identification.h).
constexpr double kBaseRankTolerance = 1e-7;

// The slot design of one pass: the caller's nominal one on the first pass when it holds every
// slot needed (not in reference mode), otherwise a linearisation at fit->errors.
Result<std::shared_ptr<const kinematics::SlotDesign>> PassDesign(
    const kinematics::MachineModel& machine, std::span<const kinematics::Observation> obs,
    const DiagnosisOptions& options, const kinematics::ErrorState& errors, const std::vector<kinematics::ErrorSlot>& slots,
    bool first_pass, bool reference_mode) {
  const auto n = static_cast<Eigen::Index>(obs.size());
  const kinematics::SlotDesign* given = options.nominal_slot_design.get();
  const bool use_given = first_pass && !reference_mode && given && given->dslot_um.rows() == n &&
                         std::all_of(slots.begin(), slots.end(), [&](const kinematics::ErrorSlot& sl) {
                           return std::find(given->slots.begin(), given->slots.end(), sl) != given->slots.end();
                         });
  if (use_given) return options.nominal_slot_design;
  auto lin = kinematics::LineariseSlots(machine, errors, slots, obs);
  if (!lin.ok()) return lin.status();
  return std::make_shared<const kinematics::SlotDesign>(std::move(*lin));
}

// Appends to X the directions the reference's uncertainty moves the deviations along
// (diagnosis_reference_nuisance.h), when the options give it.
Status AddReferenceNuisance(const kinematics::MachineModel& machine, std::span<const kinematics::Observation> obs,
                            const DiagnosisOptions& options, BaseFit* fit, Eigen::MatrixXd* X) {
  if (!options.reference || !options.reference_uncertainty) return {};
  const Eigen::MatrixXd held = MakeBasis(*X, ColumnNorms(*X), kBaseRankTolerance, true).U;  // as the base's rank
  auto nuisance = ReferenceNuisanceColumns(machine, fit->errors, obs, held, *options.reference_uncertainty,
                                           options.reference_nuisance_ratio);
  if (!nuisance.ok()) return nuisance.status();
  const Eigen::MatrixXd& N = nuisance->columns_um;
  fit->nuisance_columns = static_cast<int>(N.cols());
  fit->reference_var_um2 = nuisance->remaining_um.rowwise().squaredNorm();
  fit->reference_remaining_um = std::move(nuisance->remaining_um);
  X->conservativeResize(Eigen::NoChange, X->cols() + N.cols());
  X->rightCols(N.cols()) = N;
  return {};
}

// The linear fit of one pass on fit->design: the design [base columns, alignment, the reference's
// nuisance directions], the deviation to explain, its basis and the fitted coefficients.
Status FitPass(const kinematics::MachineModel& machine, std::span<const kinematics::Observation> obs,
               const DiagnosisOptions& options, const std::vector<int>& base_coefficients,
               const Eigen::VectorXd* reference_dev_um, BaseFit* fit) {
  const auto n = static_cast<Eigen::Index>(obs.size());
  const kinematics::SlotDesign& design = *fit->design;
  auto J_base = kinematics::CoefficientColumns(design, fit->errors, base_coefficients, obs);
  if (!J_base.ok()) return J_base.status();
  Eigen::MatrixXd X0(n, fit->q_fit + 6);
  if (fit->q_fit > 0) X0.leftCols(fit->q_fit) = *J_base;
  X0.rightCols(6) = design.lin.J_dev_alignment;
  TPCAL_RETURN_IF_ERROR(AddReferenceNuisance(machine, obs, options, fit, &X0));
  fit->y = design.lin.measured_dev_um - design.lin.predicted_dev_um;
  if (reference_dev_um) fit->y -= *reference_dev_um;
  fit->basis = MakeBasis(X0, ColumnNorms(X0), kBaseRankTolerance, true);
  const Basis& base = fit->basis;
  const Eigen::VectorXd r0 = fit->y - base.U * (base.U.transpose() * fit->y);
  const double s2 = r0.squaredNorm() / std::max<double>(1.0, static_cast<double>(n - base.rank));
  Solve(base, fit->y, s2, &fit->coef, &fit->u, &fit->identifiable);
  return {};
}

// A second linearisation at the fitted base is needed only when the fit is large enough for
// second-order terms to matter: |angle| > 1000 urad or |length| > 1000 um (below that they stay
// under lever * angle^2 = 500 mm * 1e-6 = 5e-4 um, far below any CMM noise).
bool NeedsSecondPass(const BaseFit& fit) {
  for (int k = 0; k < fit.q_fit; ++k)
    if (fit.identifiable[static_cast<std::size_t>(k)] && std::abs(fit.coef(k)) > 1000.0) return true;
  return false;
}

// Moves the linearisation point to the fitted base errors.
void MoveToFittedBase(BaseFit* fit) {
  for (int k = 0; k < fit->q_fit; ++k) {
    const int c = fit->active.coefficients[static_cast<std::size_t>(k)];
    const double per = fit->errors.coefficient_info(c).display_per_internal;
    if (fit->identifiable[static_cast<std::size_t>(k)])
      fit->errors.set_coefficient(c, fit->errors.coefficient(c) + fit->coef(k) / per);
  }
}

// " (fixed machine errors, re-alignment fitted)", or with parameters refitted on the reference
// " (fixed machine errors except E_X0C, E_A0C refitted; re-alignment fitted)".
std::string ReferenceHeld(const BaseFit& fit, const DiagnosisOptions& options) {
  const std::string nuisance =
      fit.nuisance_columns == 0 ? ""
                                : "; " + std::to_string(fit.nuisance_columns) +
                                      (fit.nuisance_columns == 1 ? " direction" : " directions") +
                                      " its own uncertainty moves the piece along, fitted";
  if (fit.q_fit == 0 || options.reference_free.empty())
    return " (fixed machine errors, re-alignment fitted" + nuisance + ")";
  std::string names;
  for (const auto& n : options.reference_free) names += (names.empty() ? "" : ", ") + n;
  return " (fixed machine errors except " + names + " refitted; re-alignment fitted" + nuisance + ")";
}

}  // namespace

Eigen::MatrixXd ReferenceShareAlong(const BaseFit& fit, const Eigen::MatrixXd& U) {
  const Eigen::MatrixXd& R = fit.reference_remaining_um;
  return R.cols() ? Eigen::MatrixXd(U.transpose() * R) : Eigen::MatrixXd(U.cols(), 0);
}

double ReferenceVarianceAlong(const BaseFit& fit, const Eigen::MatrixXd& U) {
  return ReferenceShareAlong(fit, U).squaredNorm();
}

double SsrBeyondReference(const BaseFit& fit, double ssr) { return std::max(0.0, ssr - fit.reference_var_um2.sum()); }

std::vector<kinematics::ErrorSlot> DiagnosisSlotUnion(const kinematics::ErrorState& errors,
                                                      const std::vector<int>& base_coefficients,
                                                      const std::vector<kinematics::ErrorSlot>& candidate_slots) {
  std::vector<kinematics::ErrorSlot> slots = kinematics::SlotsOf(errors, base_coefficients);
  kinematics::AddSlots(candidate_slots, &slots);
  return slots;
}

Result<BaseFit> FitBaseModel(const testpieces::TestPiece& piece, const kinematics::MachineModel& machine,
                             std::span<const kinematics::Observation> obs, const DiagnosisOptions& options,
                             const std::vector<std::string>& base_names, bool reference_mode,
                             const Eigen::VectorXd* reference_dev_um) {
  const auto n = static_cast<Eigen::Index>(obs.size());
  BaseFit fit(options.reference ? *options.reference : kinematics::ErrorState(machine));
  if (!base_names.empty()) {
    auto act = kinematics::ActivateParameters(machine, &fit.errors, base_names);
    if (!act.ok()) return act.status();
    fit.active = *act;
  }
  const bool free_on_reference = reference_mode && options.reference && !options.reference_free.empty();
  if (free_on_reference) {
    auto act = kinematics::ActivateParameters(machine, &fit.errors, options.reference_free);
    if (!act.ok()) return act.status();
    fit.active = *act;
  }
  fit.q_fit = reference_mode && !free_on_reference ? 0 : fit.active.size();
  if (n <= fit.q_fit + 6)
    return Status(StatusCode::kTooFewPoints, "diagnosis needs more than " + std::to_string(fit.q_fit + 6) +
                                                 " points for the base model, got " + std::to_string(n));
  // One slot linearisation per pass serves the base model and (the last) every machine-error
  // candidate: the union of the slots both write.
  auto candidate_slots = CandidateSlots(piece, machine, fit.errors, base_names, reference_mode);
  if (!candidate_slots.ok()) return candidate_slots.status();
  const std::vector<int> base_coefficients =
      reference_mode && !free_on_reference ? std::vector<int>{} : fit.active.coefficients;
  int passes = 1;
  for (int pass = 0; pass < passes; ++pass) {
    const auto slots = DiagnosisSlotUnion(fit.errors, base_coefficients, *candidate_slots);
    auto design = PassDesign(machine, obs, options, fit.errors, slots, pass == 0, reference_mode);
    if (!design.ok())  // linearised at the reference errors: too large ones are that file's fault
      return options.reference ? kinematics::AtErrorsFile(design.status(), options.reference_path) : design.status();
    fit.design = std::move(*design);
    TPCAL_RETURN_IF_ERROR(FitPass(machine, obs, options, base_coefficients, reference_dev_um, &fit));
    if (pass == 0 && !reference_mode && NeedsSecondPass(fit)) passes = 2;
    if (pass + 1 < passes) MoveToFittedBase(&fit);
  }
  if (free_on_reference) {
    const Eigen::MatrixXd& a = fit.design->lin.J_dev_alignment;
    const Eigen::VectorXd held = fit.y - a * a.colPivHouseholderQr().solve(fit.y);
    fit.held_rms_um = Rms(held);
  }
  // After the second pass fit.coef holds the correction at the fitted point: total = fitted + correction.
  return fit;
}

void DescribeBaseModel(const BaseFit& fit, const DiagnosisOptions& options, bool point_reference, bool reference_mode,
                       DiagnosisResult* out) {
  out->n_points = static_cast<int>(fit.y.size());
  out->reference_held_rms_um = fit.held_rms_um;
  out->base_columns = fit.basis.rank;
  out->base_model = point_reference
                        ? options.reference_name + " (reference point file: measured minus reference point by point, "
                                                   "re-alignment fitted)"
                    : reference_mode ? options.reference_name + ReferenceHeld(fit, options)
                                     : "location errors and squareness (" + std::to_string(fit.q_fit) +
                                           " parameters) + re-alignment, fitted";
  for (int k = 0; k < fit.q_fit; ++k) {
    const int c = fit.active.coefficients[static_cast<std::size_t>(k)];
    const auto& info = fit.errors.coefficient_info(c);
    EffectParameter p;
    p.name = info.name;
    p.unit = info.unit;
    p.value = fit.errors.coefficient(c) * info.display_per_internal + fit.coef(k);
    p.u = fit.u(k);
    p.identifiable = fit.identifiable[static_cast<std::size_t>(k)];
    out->base_parameters.push_back(p);
  }
}

Eigen::VectorXd NoiseScales(const testpieces::MeasuredObservations& mo) {
  const auto& obs = mo.observations;
  if (std::all_of(obs.begin(), obs.end(), [](const kinematics::Observation& o) { return o.noise_scale == 1.0; }))
    return {};
  Eigen::VectorXd scale(static_cast<Eigen::Index>(obs.size()));
  for (std::size_t i = 0; i < obs.size(); ++i) scale(static_cast<Eigen::Index>(i)) = obs[i].noise_scale;
  return scale;
}

BaseGap MakeBaseGap(const BaseFit& fit, const testpieces::MeasuredObservations& mo, double holdout_tolerance) {
  const auto& obs = mo.observations;
  const auto n = static_cast<Eigen::Index>(obs.size());
  const Eigen::MatrixXd& U = fit.basis.U;
  std::vector<int> feature_of_point(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) feature_of_point[static_cast<std::size_t>(i)] = obs[static_cast<std::size_t>(i)].group;
  GroupCrossValidation feature_cv(U, feature_of_point, static_cast<int>(mo.feature_names.size()), holdout_tolerance);
  Eigen::VectorXd r = fit.y - U * (U.transpose() * fit.y);
  GroupCvResult cv = feature_cv.Evaluate(r);
  BaseGap gap{std::move(r), RowSquaredNorms(U), 0.0, 0.0, 0.0, std::move(feature_cv), std::move(cv), mo.feature_names};
  gap.ssr = gap.r.squaredNorm();
  gap.noise_ssr = gap.ssr;
  if (const Eigen::VectorXd scale = NoiseScales(mo); scale.size() > 0) {
    gap.noise_ssr = gap.r.cwiseQuotient(scale).squaredNorm();
    gap.mean_noise_scale2 = scale.squaredNorm() / static_cast<double>(scale.size());
  }
  gap.rms_um = Rms(gap.r);
  gap.press_rms_um = Rms(Press(gap.r, gap.h));
  return gap;
}

void ReportBaseGap(const BaseGap& gap, const testpieces::MeasuredObservations& mo, DiagnosisResult* out) {
  const Eigen::VectorXd& r0 = gap.r;
  out->press_rms_um = gap.press_rms_um;
  out->cv_rms_um = gap.cv.Rms();
  out->n_features = 0;
  for (int g = 0; g < gap.feature_cv.n_groups(); ++g) out->n_features += gap.feature_cv.rows(g).empty() ? 0 : 1;
  out->cv_features = CountTrue(gap.cv.holdable);
  out->cv_not_held_out = NotHeldOut(gap, gap.cv.holdable);
  out->rms_um = gap.rms_um;
  out->max_abs_um = r0.size() ? r0.cwiseAbs().maxCoeff() : 0.0;
  out->gap_um.assign(r0.data(), r0.data() + r0.size());
  for (const auto& o : mo.observations) out->point_feature.push_back(mo.feature_names[static_cast<std::size_t>(o.group)]);
}

std::vector<std::string> NotHeldOut(const BaseGap& gap, const std::vector<bool>& holdable) {
  std::vector<std::string> names;
  for (int g = 0; g < gap.feature_cv.n_groups(); ++g)
    if (!holdable[static_cast<std::size_t>(g)] && !gap.feature_cv.rows(g).empty())
      names.push_back(gap.feature_names[static_cast<std::size_t>(g)]);
  return names;
}

int CountTrue(const std::vector<bool>& v) { return static_cast<int>(std::count(v.begin(), v.end(), true)); }

}  // namespace tpcal::pipeline::diagnosis_internal
