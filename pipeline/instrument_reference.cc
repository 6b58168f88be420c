#include "pipeline/instrument_reference.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <set>
#include <utility>

#include "kinematics/prior_update.h"
#include "pipeline/datum_ball_stage.h"
#include "pipeline/diagnosis/reference_agreement.h"
#include "pipeline/identified_gap.h"
#include "pipeline/identify_stage.h"
#include "pipeline/io/identification_reader.h"

namespace tpcal::pipeline {
namespace {

struct InstrumentResult {
  std::string instrument;
  std::string machine_type;
  std::vector<kinematics::ParameterEstimate> parameters;
};

// A tpcal.identification/1 file: its parameters as they were identified.
Result<InstrumentResult> ReadIdentified(const std::string& path) {
  auto file = ReadIdentificationJson(path);
  if (!file.ok()) return file.status();
  InstrumentResult out{file->instrument.empty() ? "identification" : file->instrument, file->machine, {}};
  for (const IdentifiedParameter& p : file->parameters) {
    kinematics::ParameterEstimate e;
    e.name = p.name, e.unit = p.unit, e.identifiable = p.identifiable, e.value = p.value, e.u = p.u;
    out.parameters.push_back(std::move(e));
  }
  return out;
}

Result<InstrumentResult> IdentifyInstrument(const InstrumentReferenceRequest& r) {
  if (IsIdentificationReference(r.path)) return ReadIdentified(r.path);
  if (!IsReferenceInstrument(r.instrument))
    return Status(StatusCode::kInvalidArgument, "--reference-instrument " + r.instrument + ": expected " + kReferenceInstruments);
  auto ball = RunDatumBallStage({.path = r.path, .machine_path = r.machine_path, .parameters = {}, .ball_part_mm = {}});
  if (!ball.ok()) return ball.status();
  return InstrumentResult{r.instrument, ball->machine, ball->result.parameters};
}

std::vector<std::string> NamesOf(const std::vector<kinematics::ParameterEstimate>& params) {
  std::vector<std::string> names;
  for (const auto& p : params) names.push_back(p.name);
  return names;
}

// The parameters the piece disagrees with (a disagreeing row, or a name in a disagreeing combination).
std::set<std::string> Disagreeing(const ReferenceAgreement& a, const std::vector<kinematics::ParameterEstimate>& params) {
  std::set<std::string> out;
  for (const AgreementRow& row : a.rows) {
    if (row.agree) continue;
    for (const auto& p : params)
      if (row.name == p.name || row.name.find(p.name) != std::string::npos) out.insert(p.name);
  }
  return out;
}

// The instrument's estimates as errors on the piece's machine (unidentifiable ones at zero); the
// active set and u (0: unknown) of the parameters the piece may update: none when `hold`.
struct Prior {
  explicit Prior(const kinematics::MachineModel& m) : errors(m) {}
  kinematics::ErrorState errors;
  kinematics::ActiveSet active;
  std::vector<std::string> names;
  std::vector<double> u;
};

Result<Prior> InstrumentPrior(const kinematics::MachineModel& m, const std::vector<kinematics::ParameterEstimate>& params,
                              bool hold) {
  Prior prior(m);
  auto all = kinematics::ActivateParameters(m, &prior.errors, NamesOf(params));
  if (!all.ok()) return all.status();
  for (std::size_t k = 0; k < params.size(); ++k) {
    const int c = all->coefficients[k];
    const bool known = params[k].identifiable;
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
    note += fmt::format(" updated by the piece within their u (largest change {} {:+.3f} {})", prior.names[worst],
                        up.delta[worst], info.unit);
  }
  if (!held.empty())
    note += fmt::format(" as measured (the piece disagrees on {}: the gap is what differs)", fmt::join(held, ", "));
  return note;
}

}  // namespace

bool IsIdentificationReference(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".json";
}

Result<DiagnosisResult> DiagnoseAgainstInstrument(const LoadedPiece& setup, const PointSet& measured,
                                                  const InstrumentReferenceRequest& r, const DiagnosisOptions& options) {
  auto inst = IdentifyInstrument(r);
  if (!inst.ok()) return inst.status();
  if (inst->machine_type != kinematics::MachineTypeName(setup.machine.type))
    return Status(StatusCode::kInvalidArgument,
                  fmt::format("a {} of a {} machine, the piece's machine is {} (give --machine)", inst->instrument,
                              inst->machine_type.empty() ? "unnamed" : inst->machine_type,
                              kinematics::MachineTypeName(setup.machine.type)),
                  r.path);
  IdentifyStageOptions id_options;
  id_options.parameters = NamesOf(inst->parameters);
  id_options.parameters_origin = r.path;
  id_options.screen_outliers = options.screen_outliers;
  auto piece = RunIdentifyStage(setup.piece, setup.machine, measured, id_options);
  if (!piece.ok()) return piece.status();
  ReferenceAgreement agreement = CompareWithReference(inst->parameters, piece->identification.parameters,
                                                      piece->identification.identifiability, options.alpha);
  const std::set<std::string> held = Disagreeing(agreement, inst->parameters);
  // Where the two agree, the piece refines the instrument within its u (a loose instrument cannot
  // raise an alarm); where they disagree, the instrument is the cold machine as measured and the
  // piece's departure from it is what the diagnosis explains (an update would absorb part of it).
  auto prior = InstrumentPrior(setup.machine, inst->parameters, !held.empty());
  if (!prior.ok()) return prior.status();
  const double sigma_um = options.noise_um > 0.0 ? options.noise_um : std::max(piece->identification.sigma_um, 1e-3);
  auto update = prior->active.size() == 0
                    ? Result<kinematics::PriorUpdate>(kinematics::PriorUpdate(prior->errors))
                    : kinematics::UpdateWithinPrior(setup.machine, prior->errors, prior->active, prior->u,
                                                    piece->observations.observations, sigma_um);
  if (!update.ok()) return update.status();
  DiagnosisOptions d_options = options;
  d_options.reference = update->posterior;
  d_options.reference_name = inst->instrument + " " + std::filesystem::path(r.path).filename().string();
  d_options.reference_path = r.path;
  auto d = DiagnoseIdentified(setup.piece, setup.machine, *piece, measured, d_options);
  if (!d.ok()) return d.status();
  agreement.instrument = inst->instrument;
  agreement.source = r.path;
  agreement.reference_note = UpdateNote(*prior, *update, held);
  d->reference_agreement = std::move(agreement);
  return d;
}

}  // namespace tpcal::pipeline
