#include "pipeline/instrument_reference_maps.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <utility>

#include "kinematics/map_location_equivalent.h"
#include "kinematics/prior_update.h"
#include "pipeline/diagnosis/reference_agreement.h"
#include "pipeline/identified_gap.h"

namespace tpcal::pipeline::instrument_reference_internal {
namespace {

// "the instrument's error maps (600 node values; 4 not identifiable by its plan, taken as 0: ...)
// as measured (...)".
std::string MapsNote(const InstrumentReference& ref, const std::string& how) {
  std::string note = fmt::format("the instrument's error maps ({} node values", ref.map_entries);
  if (!ref.not_identifiable.empty())
    note += fmt::format("; {} not identifiable by its plan, taken as 0: {}", ref.not_identifiable.size(),
                        fmt::join(ref.not_identifiable, ", "));
  if (!ref.not_separable.empty())
    note += fmt::format("; no component along what its installations cannot separate: {}", fmt::join(ref.not_separable, "; "));
  if (!ref.map_unmodelled.empty())
    note += fmt::format("; their share of {}, which its model lacks, {}", fmt::join(ref.map_unmodelled, ", "),
                        ref.map_u.empty() ? "left in them (their u unknown)" : "fitted with the re-alignment");
  else if (!ref.not_separable.empty())
    note += "; their share of the linear axes' squareness is not known here (tpcal finds it when it identifies "
            "the raw ball-bar file with its set-up)";
  return note + ") " + how;
}

// The piece's observations without the single hits its own screen flagged as outliers: one dust
// hit would pull the piece's fit on top of the maps. Its patches stay: against its own model they
// may be what the maps hold (an error motion).
std::vector<kinematics::Observation> UnflaggedObservations(const IdentifyStageResult& piece) {
  std::set<std::size_t> flagged;
  for (const auto& o : piece.outliers)
    if (o.kind == "outlier") flagged.insert(o.point_index);
  const testpieces::MeasuredObservations& mo = piece.observations;
  std::vector<kinematics::Observation> out;
  for (std::size_t i = 0; i < mo.observations.size(); ++i)
    if (!flagged.contains(mo.point_index.empty() ? i : mo.point_index[i])) out.push_back(mo.observations[i]);
  return out;
}

// The piece's noise: given, else from its neighbours, else its identification's residual (um).
double PieceSigma(const IdentifyStageResult& piece, const DiagnosisOptions& options) {
  if (options.noise_um > 0.0) return options.noise_um;
  if (piece.neighbour_sigma_um > 0.0) return piece.neighbour_sigma_um;
  return std::max(piece.identification.sigma_um, 1e-3);
}

// The maps' parameter equivalent on the piece's parameters (kinematics/map_location_equivalent.h),
// compared with the piece; `made` false (and `why`) when the maps have none: a ball bar's carry no
// component along the location errors, maps without a grid of table poses.
struct MapsComparison {
  bool made = false;
  std::string why;
  kinematics::MapEquivalent equivalent;
  ReferenceAgreement agreement;
  std::set<std::string> held;      // the piece disagrees: refitted on top of the maps as measured
  std::vector<std::string> unseen; // no number from the maps, one from the piece: fitted from it
};

// The entries the instrument determined (all but map_undetermined, whatever their u) and their
// full covariance, or their u alone, or neither (u unknown).
kinematics::MapEquivalentInput EquivalentInput(const InstrumentReference& ref) {
  kinematics::MapEquivalentInput in;
  const int n = ref.maps->num_coefficients();
  in.determined.assign(n, true);
  for (const std::string& name : ref.map_undetermined)
    if (auto c = ref.maps->FindCoefficient(name)) in.determined[*c] = false;
  if (ref.map_u.empty()) return in;
  std::vector<double> u(n, 0.0);
  for (const auto& [name, u_k] : ref.map_u)
    if (auto c = ref.maps->FindCoefficient(name)) u[*c] = u_k;
  if (ref.map_covariance.rows() == n) in.covariance = ref.map_covariance;
  else in.u = std::move(u);
  return in;
}

// The piece's own parameters on top of the maps: fitted from zero over them while the maps' nodes
// move within their u (kinematics::UpdateWithinPrior: the parameters with no prior, the
// re-alignment projected out). Its value for a parameter is the equivalent's plus that fit, its
// u the fit's, the maps' noise included (their correlations not used): so what the maps hold
// beyond location errors (error motions) enters both sides alike, and the difference is the fit.
// A parameter the piece cannot identify alone is not compared (nor its combinations).
Result<std::vector<kinematics::ParameterEstimate>> PieceOnTheMaps(const LoadedPiece& setup, const InstrumentReference& ref,
                                                                  const IdentifyStageResult& piece,
                                                                  const DiagnosisOptions& options,
                                                                  const kinematics::MapEquivalent& eq) {
  std::vector<kinematics::ParameterEstimate> out = piece.identification.parameters;
  std::vector<std::string> names;
  std::vector<double> u;
  for (const auto& p : out) names.push_back(p.name), u.push_back(0.0);
  for (const auto& [name, u_k] : ref.map_u) names.push_back(name), u.push_back(u_k);
  kinematics::ErrorState prior = *ref.maps;
  auto active = kinematics::ActivateParameters(setup.machine, &prior, names);
  if (!active.ok()) return active.status();
  auto fit = kinematics::UpdateWithinPrior(setup.machine, prior, *active, u, UnflaggedObservations(piece),
                                           PieceSigma(piece, options));
  if (!fit.ok()) return fit.status();
  for (std::size_t k = 0; k < out.size(); ++k) {
    out[k].identifiable = out[k].identifiable && fit->posterior_u[k] > 0.0;
    out[k].value = (eq.parameters[k].identifiable ? eq.parameters[k].value : 0.0) + fit->delta[k];
    out[k].u = fit->posterior_u[k];
    out[k].uncertainties.clear();
  }
  return out;
}

// The catalog name of a parameter (aliases resolved: "beta_ZX" is "E_B(0X)Z"), else the name.
std::string CanonicalName(const kinematics::MachineModel& m, const std::string& name) {
  auto info = kinematics::LookupParameter(m, name);
  return info.ok() ? info->name : name;
}

// The equivalent's parameters that the maps' table poses cannot determine, taken from the
// instrument's own estimates of them where it has one (probe_artifacts: the linear axes'
// squareness, fitted with its poses).
void TakeDirectEstimates(const kinematics::MachineModel& m, const std::vector<kinematics::ParameterEstimate>& direct,
                         std::vector<kinematics::ParameterEstimate>* equivalent) {
  for (kinematics::ParameterEstimate& e : *equivalent) {
    if (e.identifiable) continue;
    for (const kinematics::ParameterEstimate& d : direct)
      if (d.identifiable && CanonicalName(m, d.name) == CanonicalName(m, e.name) && d.unit == e.unit)
        e.identifiable = true, e.value = d.value, e.u = d.u, e.ci95_low = d.ci95_low, e.ci95_high = d.ci95_high;
  }
}

MapsComparison CompareMaps(const LoadedPiece& setup, const InstrumentReference& ref, const IdentifyStageResult& piece,
                           const DiagnosisOptions& options) {
  MapsComparison out;
  if (!ref.not_separable.empty()) {
    out.why = "its maps carry no component along the location errors";
    // No parameter equivalent: every parameter the piece identifies is fitted from it.
    for (const auto& p : piece.identification.parameters)
      if (p.identifiable) out.unseen.push_back(p.name);
    return out;
  }
  const auto& params = piece.identification.parameters;
  std::vector<std::string> names;
  for (const auto& p : params) names.push_back(p.name);
  auto eq = kinematics::ParameterEquivalentOfMaps(setup.machine, *ref.maps, names, EquivalentInput(ref));
  if (!eq.ok()) {
    out.why = eq.status().message();
    return out;
  }
  TakeDirectEstimates(setup.machine, ref.parameters, &eq->parameters);
  auto on_maps = PieceOnTheMaps(setup, ref, piece, options, *eq);
  if (!on_maps.ok()) {
    out.why = "the piece on top of the maps: " + on_maps.status().message();
    return out;
  }
  out.made = true;
  out.equivalent = std::move(*eq);
  out.agreement = CompareWithReference(out.equivalent.parameters, *on_maps, {}, options.alpha);
  out.held = DisagreeingParameters(out.agreement, out.equivalent.parameters);
  for (std::size_t k = 0; k < params.size(); ++k)
    if (!out.equivalent.parameters[k].identifiable && params[k].identifiable) out.unseen.push_back(params[k].name);
  return out;
}

// A ball bar's folded share of errors it does not model (InstrumentReference::map_unmodelled) is
// taken as this uncertainty of each (1 sd, display units: 100 urad of squareness, more than any
// machine's), so that the base model fits the directions it moves the piece along.
constexpr double kUnmodelledU = 100.0;

// Adds D diag(kUnmodelledU^2) D^T to `covariance`, D the entries' (`names`) response rows.
void AddUnmodelled(const InstrumentReference& ref, const std::vector<std::string>& names, Eigen::MatrixXd* covariance) {
  if (ref.map_unmodelled.empty()) return;
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(names.size()),
                                            static_cast<Eigen::Index>(ref.map_unmodelled.size()));
  for (std::size_t i = 0; i < names.size(); ++i)
    for (const auto& [entry, row] : ref.map_unmodelled_response)
      if (entry == names[i] && row.size() == D.cols()) D.row(static_cast<Eigen::Index>(i)) = row;
  *covariance += kUnmodelledU * kUnmodelledU * D * D.transpose();
}

// The maps' own uncertainty for the diagnosis's base model (DiagnosisOptions::
// reference_uncertainty): their determined entries with their full covariance (or their u
// alone) and the instrument's constant errors with their u (their covariance with the maps is
// not kept: the probing test reports u per constant error), plus a ball bar's share of what it
// does not model (AddUnmodelled); none when the u are unknown.
std::optional<ReferenceUncertainty> MapsUncertainty(const InstrumentReference& ref, double noise_um) {
  if (ref.map_u.empty()) return std::nullopt;
  ReferenceUncertainty out;
  out.noise_um = noise_um;
  std::vector<int> index;  // into ref.maps' coefficients, -1 for a constant error
  std::vector<double> u;
  const std::set<std::string> undetermined(ref.map_undetermined.begin(), ref.map_undetermined.end());
  for (const auto& [name, u_k] : ref.map_u) {
    auto c = ref.maps->FindCoefficient(name);
    if (!c || undetermined.contains(name) || !(u_k > 0.0)) continue;
    out.names.push_back(name), index.push_back(*c), u.push_back(u_k);
  }
  for (const auto& p : ref.parameters)
    if (p.identifiable && p.u > 0.0) out.names.push_back(p.name), index.push_back(-1), u.push_back(p.u);
  const auto m = static_cast<Eigen::Index>(out.names.size());
  const bool full = ref.map_covariance.rows() == ref.maps->num_coefficients();
  out.covariance = Eigen::MatrixXd::Zero(m, m);
  for (Eigen::Index i = 0; i < m; ++i)
    for (Eigen::Index j = 0; j < m; ++j) {
      const int a = index[static_cast<std::size_t>(i)], b = index[static_cast<std::size_t>(j)];
      if (full && a >= 0 && b >= 0) out.covariance(i, j) = ref.map_covariance(a, b);
      else if (i == j) out.covariance(i, j) = u[static_cast<std::size_t>(i)] * u[static_cast<std::size_t>(i)];
    }
  AddUnmodelled(ref, out.names, &out.covariance);
  return out;
}

// "compared through their parameter equivalent (...)", or why no parameter is compared.
std::string ComparisonNote(const MapsComparison& c) {
  if (!c.made)
    return "no parameter in common with the piece's model (" + c.why + "): compared by simulation only" +
           (c.unseen.empty() ? std::string()
                             : fmt::format("; the piece's own parameters fitted from it on top of the maps: {}",
                                           fmt::join(c.unseen, ", ")));
  std::string note = fmt::format(
      "compared through their parameter equivalent (the piece's parameters that best reproduce the maps' table "
      "poses at {} positions, leaving {:.2f} um and {:.1f} urad RMS{})",
      c.equivalent.positions, c.equivalent.residual_rms_um, c.equivalent.residual_rms_urad,
      c.equivalent.u_known ? "" : "; their u unknown");
  if (!c.unseen.empty())
    note += fmt::format("; not seen by the instrument, fitted from the piece on top of the maps: {}", fmt::join(c.unseen, ", "));
  if (!c.held.empty())
    note += fmt::format("; the piece disagrees on {}: refitted on top of the maps as measured (the gap with them held "
                        "is reference_held_rms_um)",
                        fmt::join(c.held, ", "));
  return note;
}

}  // namespace

// The piece's own outlier screen flags what its model lacks and the maps may hold (an error
// motion): the piece is identified with every point and the diagnosis screens against the maps.
// The caller's identification serves when its screen flagged nothing. Where the maps have a
// parameter equivalent, the piece's parameters the maps cannot see are fitted from the piece and
// those it disagrees on are refitted on top of the maps. The gap is taken against the maps as
// measured, the directions their own uncertainty moves the piece along fitted in the base model
// (DiagnosisOptions::reference_uncertainty): a loose instrument's noise is not blamed on the piece.
Result<DiagnosisResult> DiagnoseAgainstMaps(const LoadedPiece& setup, const PointSet& measured, const InstrumentReference& ref,
                                            const DiagnosisOptions& options, const IdentifyStageResult* identified) {
  const bool unscreened = identified != nullptr && identified->outliers.empty() && identified->local_defects.empty();
  DiagnosisOptions keep_all = options;
  keep_all.screen_outliers = false;
  auto piece = PieceForReference(setup, measured, {}, ref.source, keep_all, unscreened ? identified : nullptr);
  if (!piece.ok()) return piece.status();
  MapsComparison cmp = CompareMaps(setup, ref, *piece, options);
  std::optional<ReferenceUncertainty> uncertainty = MapsUncertainty(ref, PieceSigma(*piece, options));
  const std::string how = uncertainty ? "as measured, the directions their u moves the piece along fitted with the "
                                        "re-alignment (the base model says how many)"
                                      : "as measured (their u unknown)";
  piece->outliers.clear(), piece->local_defects.clear();
  DiagnosisOptions d_options = OptionsForReference(options, ref, *ref.maps);
  d_options.reference_free.assign(cmp.held.begin(), cmp.held.end());
  d_options.reference_free.insert(d_options.reference_free.end(), cmp.unseen.begin(), cmp.unseen.end());
  d_options.reference_uncertainty = std::move(uncertainty);
  auto d = DiagnoseIdentified(setup.piece, setup.machine, *piece, measured, d_options);
  if (!d.ok()) return d.status();
  ReferenceAgreement agreement = cmp.made ? std::move(cmp.agreement) : ReferenceAgreement{};
  if (!cmp.made) agreement.alpha = options.alpha, agreement.p_threshold = options.alpha;
  agreement.instrument = ref.instrument;
  agreement.source = ref.source;
  agreement.reference_note = MapsNote(ref, how) + "; " + ComparisonNote(cmp);
  d->reference_agreement = std::move(agreement);
  return d;
}

}  // namespace tpcal::pipeline::instrument_reference_internal
