#include "pipeline/instrument_reference_maps.h"

#include <boost/math/distributions/fisher_f.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

#include "kinematics/prior_update.h"
#include "pipeline/identified_gap.h"

namespace tpcal::pipeline::instrument_reference_internal {
namespace {

// "the instrument's error maps (600 node values; 4 not identifiable by its plan, taken as 0: ...)
// as measured (...); no parameter in common with the piece's model: compared by simulation only".
std::string MapsNote(const InstrumentReference& ref, const std::string& how) {
  std::string note = fmt::format("the instrument's error maps ({} node values", ref.map_entries);
  if (!ref.not_identifiable.empty())
    note += fmt::format("; {} not identifiable by its plan, taken as 0: {}", ref.not_identifiable.size(),
                        fmt::join(ref.not_identifiable, ", "));
  if (!ref.not_separable.empty())
    note += fmt::format("; no component along what its installations cannot separate: {}", fmt::join(ref.not_separable, "; "));
  return note + ") " + how + "; no parameter in common with the piece's model: compared by simulation only";
}

// The piece's observations without the single hits its own screen flagged as outliers: one dust
// hit would fail the global test below by itself. Its patches stay: against its own model they
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

// p of the conflict test: chi2 for a known noise (options.noise_um), else F(dof, nu) with the
// neighbour sigma's nu degrees of freedom (an estimated sigma scatters too); NaN when untestable.
double ConflictP(const kinematics::PriorUpdate& up, const IdentifyStageResult& piece, const DiagnosisOptions& options) {
  if (options.noise_um > 0.0 || !(piece.neighbour_sigma_um > 0.0 && piece.neighbour_sigma_dof > 30.0) ||
      std::isnan(up.conflict_p))
    return up.conflict_p;
  const boost::math::fisher_f f(up.conflict_dof, piece.neighbour_sigma_dof);
  return boost::math::cdf(boost::math::complement(f, std::max(0.0, up.conflict_chi2 / up.conflict_dof)));
}

// The maps updated by the piece within their u when the piece agrees with them (conflict p >=
// alpha), as measured otherwise; `how` says which, with the test.
Result<kinematics::ErrorState> MapsForThePiece(const LoadedPiece& setup, const InstrumentReference& ref,
                                               const IdentifyStageResult& piece, const DiagnosisOptions& options,
                                               std::string* how) {
  *how = "as measured (their u unknown)";
  if (ref.map_u.empty()) return *ref.maps;
  std::vector<std::string> names;
  std::vector<double> u;
  for (const auto& [name, u_k] : ref.map_u) names.push_back(name), u.push_back(u_k);
  auto active = kinematics::SelectCoefficients(*ref.maps, names);
  if (!active.ok()) {
    *how = "as measured (their u name no coefficient of the maps: " + active.status().message() + ")";
    return *ref.maps;
  }
  const bool known = options.noise_um > 0.0, neighbours = piece.neighbour_sigma_um > 0.0;
  const double sigma_um = known ? options.noise_um
                          : neighbours ? piece.neighbour_sigma_um
                                       : std::max(piece.identification.sigma_um, 1e-3);
  auto up = kinematics::UpdateWithinPrior(setup.machine, *ref.maps, *active, u, UnflaggedObservations(piece), sigma_um);
  if (!up.ok()) return up.status();
  const double p = ConflictP(*up, piece, options);
  const std::string test =
      fmt::format("chi2 {:.0f} on {} at noise {:.2f} um ({}), p = {:.2g}", up->conflict_chi2, up->conflict_dof, sigma_um,
                  known ? "given" : neighbours ? fmt::format("from neighbours, {:.0f} dof", piece.neighbour_sigma_dof)
                                               : "the identification's residual",
                  p);
  if (std::isnan(p)) {
    *how = "as measured (the piece cannot test them: " + test + ")";
    return *ref.maps;
  }
  if (p < options.alpha) {
    *how = "as measured (the piece departs from them beyond their u and its noise: " + test + ")";
    return *ref.maps;
  }
  *how = "updated by the piece within their u (the piece agrees with them: " + test + ")";
  return up->posterior;
}

// The piece's own outlier screen flags what its model lacks and the maps may hold (an error
// motion): the piece is identified with every point and the diagnosis screens against the maps.
// The caller's identification serves when its screen flagged nothing.
}  // namespace

Result<DiagnosisResult> DiagnoseAgainstMaps(const LoadedPiece& setup, const PointSet& measured, const InstrumentReference& ref,
                                      const DiagnosisOptions& options, const IdentifyStageResult* identified) {
  const bool unscreened = identified != nullptr && identified->outliers.empty() && identified->local_defects.empty();
  DiagnosisOptions keep_all = options;
  keep_all.screen_outliers = false;
  auto piece = PieceForReference(setup, measured, {}, ref.source, keep_all, unscreened ? identified : nullptr);
  if (!piece.ok()) return piece.status();
  std::string how;
  auto maps = MapsForThePiece(setup, ref, *piece, options, &how);
  if (!maps.ok()) return maps.status();
  piece->outliers.clear(), piece->local_defects.clear();
  auto d = DiagnoseIdentified(setup.piece, setup.machine, *piece, measured, OptionsForReference(options, ref, std::move(*maps)));
  if (!d.ok()) return d.status();
  ReferenceAgreement agreement;
  agreement.alpha = options.alpha, agreement.p_threshold = options.alpha;
  agreement.instrument = ref.instrument;
  agreement.source = ref.source;
  agreement.reference_note = MapsNote(ref, how);
  d->reference_agreement = std::move(agreement);
  return d;
}

}  // namespace tpcal::pipeline::instrument_reference_internal
