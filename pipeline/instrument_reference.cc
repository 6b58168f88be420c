#include "pipeline/instrument_reference.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <utility>

#include "core/ascii.h"
#include "kinematics/error_parameters.h"
#include "kinematics/errors_yaml.h"
#include "kinematics/prior_update.h"
#include "pipeline/ballbar_stage.h"
#include "pipeline/datum_ball_stage.h"
#include "pipeline/diagnosis/reference_agreement.h"
#include "pipeline/identified_gap.h"
#include "pipeline/identify_stage.h"
#include "pipeline/instrument_reference_maps.h"
#include "pipeline/io/identification_reader.h"
#include "pipeline/probe_artifacts_stage.h"

namespace tpcal::pipeline {
namespace {

Status IrCheckMachine(const LoadedPiece& setup, const InstrumentReference& ref, const std::string& path) {
  if (ref.machine_type == kinematics::MachineTypeName(setup.machine.type)) return Status::Ok();
  return Status(StatusCode::kInvalidArgument,
                fmt::format("a {} of a {} machine, the piece's machine is {} (give --machine)", ref.instrument,
                            ref.machine_type.empty() ? "unnamed" : ref.machine_type,
                            kinematics::MachineTypeName(setup.machine.type)),
                path);
}

// The instrument's tpcal.errors/1 (its --errors-out) on the piece's machine.
Status IrSetMaps(const LoadedPiece& setup, const std::string& errors_yaml, const std::string& path,
                 InstrumentReference* out) {
  TPCAL_RETURN_IF_ERROR(IrCheckMachine(setup, *out, path));
  auto maps = kinematics::ParseErrorState(errors_yaml, path, setup.machine);
  if (!maps.ok()) return maps.status();
  out->maps = std::move(*maps);
  return Status::Ok();
}

// A tpcal.identification/1 file: its parameters as they were identified, or an error-map
// instrument's maps (its "errors_yaml", on the piece's machine).
Result<InstrumentReference> IrReadIdentified(const LoadedPiece& setup, const std::string& path) {
  auto file = ReadIdentificationJson(path);
  if (!file.ok()) return file.status();
  InstrumentReference out;
  out.instrument = file->instrument.empty() ? "identification" : file->instrument;
  out.machine_type = file->machine;
  for (const IdentifiedParameter& p : file->parameters) {
    kinematics::ParameterEstimate e;
    e.name = p.name, e.unit = p.unit, e.identifiable = p.identifiable, e.value = p.value, e.u = p.u;
    out.parameters.push_back(std::move(e));
  }
  const auto n = static_cast<Eigen::Index>(file->parameters.size());
  if (!file->parameter_covariance.empty()) {
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    const Eigen::MatrixXd cov = Eigen::Map<const RowMajor>(file->parameter_covariance.data(), n, n);
    out.parameter_covariance = 0.5 * (cov + cov.transpose());  // symmetric to 1e-9 as read; exactly here
  }
  if (!file->errors_yaml.empty()) {
    out.map_entries = file->map_entries;
    out.not_identifiable = file->not_identifiable;
    out.not_separable = file->not_separable;
    out.map_u = file->map_u;
    out.map_undetermined = file->map_undetermined;
    out.map_unmodelled = file->map_unmodelled;
    for (const auto& [entry, row] : file->map_unmodelled_response)
      out.map_unmodelled_response.emplace_back(entry, Eigen::Map<const Eigen::RowVectorXd>(row.data(), static_cast<Eigen::Index>(row.size())));
    TPCAL_RETURN_IF_ERROR(IrCheckMachine(setup, out, path));
    TPCAL_RETURN_IF_ERROR(IrSetMaps(setup, file->errors_yaml, path + " (its errors_yaml)", &out));
  }
  return out;
}

// The maps' covariance in the coefficient order of out->maps (by name; its constant errors get
// zero rows); left empty when a name is missing.
void IrSetMapCovariance(const kinematics::ErrorMaps& maps, InstrumentReference* out) {
  const auto n = static_cast<Eigen::Index>(maps.entries.size());
  if (maps.covariance.rows() != n) return;
  std::vector<Eigen::Index> at(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    auto c = out->maps->FindCoefficient(maps.entries[k].coefficient);
    if (!c) return;
    at[k] = *c;
  }
  const Eigen::Index all = out->maps->num_coefficients();  // the maps' entries and constant errors
  out->map_covariance = Eigen::MatrixXd::Zero(all, all);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) out->map_covariance(at[i], at[j]) = maps.covariance(i, j);
}

Result<InstrumentReference> IrProbeArtifacts(const LoadedPiece& setup, const InstrumentReferenceRequest& r) {
  ProbeArtifactsRequest request;
  request.path = r.path, request.artifacts_path = r.setup_path, request.machine_path = r.machine_path;
  request.probe_radius_mm = r.probe_radius_mm.value_or(request.probe_radius_mm);
  auto report = RunProbeArtifactsStage(request);
  if (!report.ok()) return report.status();
  InstrumentReference out;
  out.instrument = r.instrument;
  out.machine_type = report->machine;
  out.map_entries = static_cast<int>(report->result.maps.entries.size());
  out.not_identifiable = report->result.maps.not_identifiable;
  out.parameters = report->result.poses.linear_errors;
  for (const auto& e : report->result.maps.entries) {
    if (e.identifiable && e.u > 0.0) out.map_u.emplace_back(e.coefficient, e.u);
    if (!e.identifiable) out.map_undetermined.push_back(e.coefficient);
  }
  TPCAL_RETURN_IF_ERROR(IrSetMaps(setup, report->errors_yaml, r.path, &out));
  IrSetMapCovariance(report->result.maps, &out);
  return out;
}

Result<InstrumentReference> IrBallbar(const LoadedPiece& setup, const InstrumentReferenceRequest& r) {
  if (r.setup_path.empty())
    return Status(StatusCode::kInvalidArgument,
                  "--reference-instrument ballbar needs its set-up (--reference-setup S.yaml, tpcal.ballbar_setup/1)",
                  r.path);
  auto report = RunBallbarStage({.path = r.path,
                                 .setup_path = r.setup_path,
                                 .machine_path = r.machine_path,
                                 .map_response_to = kinematics::LinearSquarenessSet()});
  if (!report.ok()) return report.status();
  if (report->errors_yaml.empty())
    return Status(StatusCode::kInvalidArgument,
                  "the ball-bar test has no rotary installation: no error maps to diagnose against", r.path);
  InstrumentReference out;
  out.instrument = r.instrument;
  out.machine_type = report->machine;
  for (const BallbarAxisReport& a : report->axes) {
    out.map_entries += static_cast<int>(a.result.entries.size());
    for (const auto& e : a.result.entries)
      if (e.identifiable && e.u > 0.0) out.map_u.emplace_back(e.coefficient, e.u);
    for (const std::string& n : a.result.not_identifiable) out.not_identifiable.push_back(n);
    for (const std::string& f : a.result.not_separable) out.not_separable.push_back(a.axis + ": " + f);
    out.map_unmodelled = a.response_to;  // the same names for every axis of one machine
    for (std::size_t i = 0; i < a.result.entries.size() && a.map_response.cols() > 0; ++i)
      out.map_unmodelled_response.emplace_back(a.result.entries[i].coefficient,
                                               a.map_response.row(static_cast<Eigen::Index>(i)));
  }
  TPCAL_RETURN_IF_ERROR(IrSetMaps(setup, report->errors_yaml, r.path, &out));
  return out;
}

Result<InstrumentReference> IrIdentify(const LoadedPiece& setup, const InstrumentReferenceRequest& r) {
  if (r.probe_radius_mm && IsIdentificationReference(r.path))
    return Status(StatusCode::kInvalidArgument,
                  "a stylus radius (--reference-probe-radius-mm) is for a probing test's raw file: an identification "
                  "JSON was identified with its own",
                  r.path);
  if (IsIdentificationReference(r.path)) return IrReadIdentified(setup, r.path);
  if (!IsReferenceInstrument(r.instrument))
    return Status(StatusCode::kInvalidArgument,
                  "--reference-instrument '" + r.instrument + "': expected " + kReferenceInstruments);
  if (r.probe_radius_mm && r.instrument != "probe_artifacts")
    return Status(StatusCode::kInvalidArgument,
                  "a stylus radius (--reference-probe-radius-mm) is for --reference-instrument probe_artifacts, not " +
                      r.instrument,
                  r.path);
  if (r.instrument == "probe_artifacts") return IrProbeArtifacts(setup, r);
  if (r.instrument == "ballbar") return IrBallbar(setup, r);
  if (!r.setup_path.empty())
    return Status(StatusCode::kInvalidArgument,
                  "--reference-setup is for probe_artifacts (its artifacts) or ballbar (its set-up), not datum_ball",
                  r.setup_path);
  auto ball = RunDatumBallStage({.path = r.path, .machine_path = r.machine_path, .parameters = {}, .ball_part_mm = {}});
  if (!ball.ok()) return ball.status();
  InstrumentReference out;
  out.instrument = r.instrument;
  out.machine_type = ball->machine;
  out.parameters = ball->result.parameters;
  out.parameter_covariance = ball->result.covariance;
  return out;
}

std::vector<std::string> NamesOf(const std::vector<kinematics::ParameterEstimate>& params) {
  std::vector<std::string> names;
  for (const auto& p : params) names.push_back(p.name);
  return names;
}

// The instrument's estimates as errors on the piece's machine; the active set and u (0: unknown)
// of the parameters the piece may update (none when `hold`), and their covariance when the
// instrument gives it. Without it unidentifiable ones are at zero; with it at the instrument's
// values, which its covariance weighs only along the combinations it determines.
struct Prior {
  explicit Prior(const kinematics::MachineModel& m) : errors(m) {}
  kinematics::ErrorState errors;
  kinematics::ActiveSet active;
  std::vector<std::string> names;
  std::vector<double> u;
  Eigen::MatrixXd covariance;  // empty: u alone
};

Result<Prior> InstrumentPrior(const kinematics::MachineModel& m, const std::vector<kinematics::ParameterEstimate>& params,
                              const Eigen::MatrixXd& covariance, bool hold) {
  Prior prior(m);
  auto all = kinematics::ActivateParameters(m, &prior.errors, NamesOf(params));
  if (!all.ok()) return all.status();
  const auto n = static_cast<Eigen::Index>(params.size());
  if (!hold && covariance.rows() == n && covariance.cols() == n) prior.covariance = covariance;
  for (std::size_t k = 0; k < params.size(); ++k) {
    const int c = all->coefficients[k];
    const bool known = params[k].identifiable || prior.covariance.size() > 0;
    prior.errors.set_coefficient(c, known ? params[k].value / prior.errors.coefficient_info(c).display_per_internal : 0.0);
    if (hold) continue;
    prior.active.coefficients.push_back(c);
    prior.names.push_back(params[k].name);
    prior.u.push_back(known ? params[k].u : 0.0);
  }
  return prior;
}

// "the instrument's errors updated by the piece within their u (largest change E_X0C +0.8 um)", or
// "the instrument's errors as measured (the piece disagrees on E_X0C: the gap is what differs)".
std::string UpdateNote(const Prior& prior, const kinematics::PriorUpdate& up, const std::set<std::string>& held) {
  std::string note = "the instrument's errors";
  if (!up.delta.empty()) {
    std::size_t worst = 0;
    for (std::size_t k = 1; k < up.delta.size(); ++k)
      if (std::abs(up.delta[k]) > std::abs(up.delta[worst])) worst = k;
    const auto& info = prior.errors.coefficient_info(prior.active.coefficients[worst]);
    note += fmt::format(" updated by the piece within their {} (largest change {} {:+.3f} {})",
                        prior.covariance.size() > 0 ? "covariance" : "u", prior.names[worst], up.delta[worst], info.unit);
  }
  if (!held.empty())
    note += fmt::format(" as measured, except {}, on which the piece disagrees: refitted on top of them (the gap "
                        "with them held is reference_held_rms_um), the candidates explain what is left",
                        fmt::join(held, ", "));
  return note;
}

}  // namespace

bool IsIdentificationReference(const std::string& path) {
  return AsciiLower(std::filesystem::path(path).extension().string()) == ".json";
}

Result<InstrumentReference> IdentifyInstrumentReference(const LoadedPiece& setup, const InstrumentReferenceRequest& r) {
  auto ref = IrIdentify(setup, r);
  if (!ref.ok()) return ref.status();
  TPCAL_RETURN_IF_ERROR(IrCheckMachine(setup, *ref, r.path));
  ref->source = r.path;
  return ref;
}

std::set<std::string> DisagreeingParameters(const ReferenceAgreement& a,
                                            const std::vector<kinematics::ParameterEstimate>& params) {
  std::set<std::string> out;
  for (const AgreementRow& row : a.rows) {
    if (row.agree) continue;
    for (const auto& p : params)
      if (std::find(row.members.begin(), row.members.end(), p.name) != row.members.end()) out.insert(p.name);
  }
  return out;
}

namespace instrument_reference_internal {

// The piece identified with `names` (the instrument's), or the caller's identification when its
// parameters are those (any set for maps: `names` empty).
Result<IdentifyStageResult> PieceForReference(const LoadedPiece& setup, const PointSet& measured, const std::vector<std::string>& names,
                                    const std::string& origin, const DiagnosisOptions& options,
                                    const IdentifyStageResult* identified) {
  if (identified != nullptr && (names.empty() || identified->parameters == names)) return *identified;
  IdentifyStageOptions id_options;
  id_options.parameters = names;
  id_options.parameters_origin = origin;
  id_options.screen_outliers = options.screen_outliers;
  return RunIdentifyStage(setup.piece, setup.machine, measured, id_options);
}

DiagnosisOptions OptionsForReference(const DiagnosisOptions& options, const InstrumentReference& ref,
                                    kinematics::ErrorState reference) {
  DiagnosisOptions d = options;
  d.reference = std::move(reference);
  d.reference_name = ref.instrument + " " + std::filesystem::path(ref.source).filename().string();
  d.reference_path = ref.source;
  return d;
}

}  // namespace instrument_reference_internal

Result<DiagnosisResult> DiagnoseAgainstInstrument(const LoadedPiece& setup, const PointSet& measured,
                                                  const InstrumentReference& ref, const DiagnosisOptions& options,
                                                  const IdentifyStageResult* identified) {
  if (ref.maps) return instrument_reference_internal::DiagnoseAgainstMaps(setup, measured, ref, options, identified);
  auto piece = instrument_reference_internal::PieceForReference(setup, measured, NamesOf(ref.parameters), ref.source,
                                                              options, identified);
  if (!piece.ok()) return piece.status();
  ReferenceAgreement agreement = CompareWithReference(ref.parameters, piece->identification.parameters,
                                                      piece->identification.identifiability, options.alpha);
  const std::set<std::string> held = DisagreeingParameters(agreement, ref.parameters);
  // Where the two agree, the piece refines the instrument within its u (a loose instrument cannot
  // raise an alarm); where they disagree, the instrument is the cold machine as measured (an update
  // would absorb part of the departure), and those parameters are refitted on top of it: a drift
  // of a tilt leaves its mean there as changed location errors, and only what remains is the
  // effect's own signature for the catalogue.
  auto prior = InstrumentPrior(setup.machine, ref.parameters, ref.parameter_covariance, !held.empty());
  if (!prior.ok()) return prior.status();
  const double sigma_um = options.noise_um > 0.0 ? options.noise_um : std::max(piece->identification.sigma_um, 1e-3);
  const auto& obs = piece->observations.observations;
  auto update = prior->active.size() == 0 ? Result<kinematics::PriorUpdate>(kinematics::PriorUpdate(prior->errors))
                : prior->covariance.size() > 0
                    ? kinematics::UpdateWithinPriorCovariance(setup.machine, prior->errors, prior->active,
                                                              prior->covariance, obs, sigma_um)
                    : kinematics::UpdateWithinPrior(setup.machine, prior->errors, prior->active, prior->u, obs, sigma_um);
  if (!update.ok()) return update.status();
  DiagnosisOptions d_options = instrument_reference_internal::OptionsForReference(options, ref, update->posterior);
  d_options.reference_free.assign(held.begin(), held.end());
  auto d = DiagnoseIdentified(setup.piece, setup.machine, *piece, measured, d_options);
  if (!d.ok()) return d.status();
  agreement.instrument = ref.instrument;
  agreement.source = ref.source;
  agreement.reference_note = UpdateNote(*prior, *update, held);
  agreement.piece_outliers = piece->outliers;
  agreement.piece_local_defects = piece->local_defects;
  d->reference_agreement = std::move(agreement);
  return d;
}

Result<DiagnosisResult> DiagnoseAgainstInstrument(const LoadedPiece& setup, const PointSet& measured,
                                                  const InstrumentReferenceRequest& r, const DiagnosisOptions& options) {
  auto ref = IdentifyInstrumentReference(setup, r);
  if (!ref.ok()) return ref.status();
  return DiagnoseAgainstInstrument(setup, measured, *ref, options);
}

}  // namespace tpcal::pipeline
