#include "pipeline/diagnosis/diagnosis_verdict.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <tuple>
#include <vector>

#include "core/parallel.h"
#include "pipeline/diagnosis/diagnosis_least_squares.h"
#include "pipeline/diagnosis/diagnosis_pair_fit.h"
#include "pipeline/diagnosis/diagnosis_projection.h"

namespace tpcal::pipeline::diagnosis_internal {
namespace {

// FBeyond's test, not remembered.
std::pair<double, double> ComputeFBeyond(const VerdictInputs& in, std::size_t j, std::size_t k) {
  const Eigen::MatrixXd& U0 = in.fit.basis.U;
  const Projected& bk = in.scored.bases[k];
  const Eigen::VectorXd& r0 = in.gap.r;
  Eigen::MatrixXd Q(r0.size(), U0.cols() + bk.U.cols());
  Q << U0, bk.U;
  // Residual after the base and candidate k, and the test of adding candidate j to it.
  const Eigen::VectorXd rk = r0 - bk.U * (bk.U.transpose() * r0);
  Projected bj = ProjectCandidate(ColumnsOf(in.catalogue.candidates[j]), Q, in.options.absorbed_tolerance);
  if (bj.rank == 0) return {0.0, 1.0};
  const Eigen::VectorXd rjk = rk - bj.U * (bj.U.transpose() * rk);
  const double dof = static_cast<double>(r0.size() - Q.cols() - bj.rank);
  if (dof <= 0 || rjk.squaredNorm() <= 0) return {0.0, 1.0};
  const double f = ((rk.squaredNorm() - rjk.squaredNorm()) / bj.rank) / (rjk.squaredNorm() / dof);
  return {f, FUpperTail(f, bj.rank, dof)};
}

// FBeyond(in, j, k) for each {j, k} of `pairs`, in order: those not yet in in.f_beyond on several
// threads from kParallelMinPoints points (each is a projection of every row: 10^5 points, a sixth
// of a diagnosis on one thread, perf), then remembered.
std::vector<std::pair<double, double>> FBeyondEach(const VerdictInputs& in,
                                                   const std::vector<std::pair<std::size_t, std::size_t>>& pairs) {
  std::vector<std::pair<std::size_t, std::size_t>> missing;
  for (const auto& jk : pairs)
    if (!in.f_beyond.contains(jk) && std::find(missing.begin(), missing.end(), jk) == missing.end())
      missing.push_back(jk);
  std::vector<std::pair<double, double>> computed(missing.size());
  ParallelForEach(missing.size(), static_cast<std::size_t>(in.gap.r.size()) >= kParallelMinPoints,
                  [&](std::size_t i) { computed[i] = ComputeFBeyond(in, missing[i].first, missing[i].second); });
  for (std::size_t i = 0; i < missing.size(); ++i) in.f_beyond.emplace(missing[i], computed[i]);
  std::vector<std::pair<double, double>> out;
  out.reserve(pairs.size());
  for (const auto& jk : pairs) out.push_back(in.f_beyond.at(jk));
  return out;
}

// The verdict's family, name and shrink, and the families whose best candidate leaves no
// significant room for the verdict (the data cannot tell them apart).
void NameVerdict(const VerdictInputs& in, const Ranking& ranking, std::size_t v, DiagnosisResult* out) {
  const auto& results = in.scored.results;
  const auto& best = results[v];
  out->verdict.family = best.family;
  out->verdict.name = best.name;
  out->verdict.shrink_pct = best.shrink_pct;
  out->verdict.cv_shrink_pct = best.cv_shrink_pct;
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  std::vector<std::string> families;
  for (const auto& [family, k] : ranking.best_of_family)
    if (family != best.family && results[k].significant) pairs.emplace_back(v, k), families.push_back(family);
  const auto f = FBeyondEach(in, pairs);
  for (std::size_t i = 0; i < pairs.size(); ++i)
    if (f[i].second > in.options.alpha) out->verdict.indistinguishable_from.push_back(families[i]);
}

// On this piece and plan: a family one of whose candidates reproduces most of the verdict's
// fitted signature s_v (its projected columns capture >= options.alias_capture of |s_v|^2)
// explains the gap about as well, whatever the F-test says at high signal: what still tells
// them apart is only the shape each candidate assumes (e.g. a quartic straightness against a
// 2-to-5-lobe radial motion along a cone section, where X is a function of C). Such a family
// is not offered as the runner-up either.
void AddAliases(const VerdictInputs& in, std::size_t v, DiagnosisResult* out) {
  const auto& results = in.scored.results;
  const auto& bases = in.scored.bases;
  const Eigen::VectorXd s_v = bases[v].U * (bases[v].U.transpose() * in.gap.r);
  const double e_v = s_v.squaredNorm();
  auto& ind = out->verdict.indistinguishable_from;
  for (std::size_t k = 0; k < results.size() && e_v > 0; ++k) {
    const std::string& family = results[k].family;
    if (family == results[v].family || !results[k].observable || std::find(ind.begin(), ind.end(), family) != ind.end())
      continue;
    const double captured = (bases[k].U.transpose() * s_v).squaredNorm() / e_v;
    if (captured >= in.options.alias_capture) ind.push_back(family);
  }
  std::sort(ind.begin(), ind.end());
}

// Whether candidate k's fitted directions hold all of candidate v's (a larger form of the same
// effect: a quartic beside a quadratic straightness), to 1e-6 of v's rank.
bool HoldsAllOf(const ScoredCandidates& scored, std::size_t k, std::size_t v) {
  const auto& bk = scored.bases[k];
  const auto& bv = scored.bases[v];
  if (bv.rank == 0 || bk.rank < bv.rank) return false;
  return (bk.U.transpose() * bv.U).squaredNorm() >= static_cast<double>(bv.rank) * (1.0 - 1e-6);
}

// The candidates, one by one, that explain the gap about as well as the verdict's candidate v:
// significant with the verdict adding nothing significant beyond them (NameVerdict's test), or
// reproducing its signature (AddAliases's), in ranking order; not `also`'s family, nor a larger
// form of the verdict's own (which passes both tests by holding it). So each family in
// indistinguishable_from has at least the candidate that put it there.
void NameIndistinguishableCandidates(const VerdictInputs& in, const Ranking& ranking, std::size_t v,
                                     DiagnosisResult* out) {
  const auto& results = in.scored.results;
  const auto& bases = in.scored.bases;
  const Eigen::VectorXd s_v = bases[v].U * (bases[v].U.transpose() * in.gap.r);
  const double e_v = s_v.squaredNorm();
  auto& names = out->verdict.indistinguishable_candidates;
  names.clear();
  std::vector<std::size_t> ks;
  std::vector<std::pair<std::size_t, std::size_t>> tested;
  for (auto k : ranking.order) {
    if (k == v || !results[k].observable || (out->verdict.also && results[k].family == *out->verdict.also)) continue;
    if (results[k].family == results[v].family && HoldsAllOf(in.scored, k, v)) continue;
    ks.push_back(k);
    if (results[k].significant) tested.emplace_back(v, k);
  }
  const auto f = FBeyondEach(in, tested);
  std::size_t t = 0;
  for (auto k : ks) {
    const bool as_well = results[k].significant && f[t++].second > in.options.alpha;
    const bool alias = e_v > 0 && (bases[k].U.transpose() * s_v).squaredNorm() / e_v >= in.options.alias_capture;
    if (as_well || alias) names.push_back(results[k].name);
  }
}

struct RunnerUp {
  std::optional<std::size_t> k;
  double p = 1.0, f = 0.0;
};

// The runner-up: of the candidates of the other families (not indistinguishable from the
// verdict), the one that adds most beyond base + verdict (largest F: a forward-selection step).
// Every candidate, not each family's best alone: what adds most beside the verdict need not be
// what explains most alone, and alpha_each is already the level of one test among all candidates.
RunnerUp FindRunnerUp(const VerdictInputs& in, std::size_t v, const Verdict& verdict) {
  const auto& results = in.scored.results;
  const auto& ind = verdict.indistinguishable_from;
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (std::size_t k = 0; k < results.size(); ++k) {
    const std::string& family = results[k].family;
    // Not only the candidates significant on their own: beside a strong verdict a second effect
    // is tested against a residual the verdict inflates (servo glitches beside a probe-radius error).
    if (results[k].observable && family != results[v].family && std::find(ind.begin(), ind.end(), family) == ind.end())
      pairs.emplace_back(k, v);
  }
  const auto fp = FBeyondEach(in, pairs);
  RunnerUp runner;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    // The largest F (p underflows to 0 for several strong effects; F still orders them).
    const auto [f, p] = fp[i];
    if (!runner.k || f > runner.f) runner.k = pairs[i].first, runner.p = p, runner.f = f;
  }
  return runner;
}

// A second effect that is not significant on its own is named only when the pair also predicts
// better, cross-validated: at most `ratio` of the verdict's held-out mean square is left
// (PairCvMeanSquareRatio).
bool PairPredictsBetter(const std::optional<PairFit>& pair, const CandidateResult& verdict, double ratio) {
  if (!pair) return false;
  // The verdict's held-out RMS by the pair's method (leave-one-feature-out, or PRESS); a pair
  // held out by features beside a verdict held out by points has no common figure: named.
  const bool pair_by_features = pair->cv_method == "leave-one-feature-out";
  if (pair_by_features && verdict.cv_method != "leave-one-feature-out") return true;
  const double alone = pair_by_features ? verdict.cv_rms_after_um : verdict.press_rms_after_um;
  return pair->cv_rms_after_um * pair->cv_rms_after_um <= ratio * alone * alone;
}

// The share of the verdict's held-out mean square the pair may leave: 90 %, so that a model
// mismatch of the verdict's effect, taken up in sample by another family, does not pass; 100 %
// (any held-out gain) when the runner-up's test beyond the verdict passes at alpha_each squared.
// On the turning piece at 5x, second effects that add with p ~ 1e-7 to 1e-14 (a scale error beside
// an angular positioning of C, a straightness beside a tilt motion of C) left 92-96 % of it.
double PairCvMeanSquareRatio(const VerdictInputs& in, const RunnerUp& runner) {
  return runner.k && runner.p < in.scored.alpha_each * in.scored.alpha_each ? 1.0 : 0.9;
}

// The candidate fitted jointly with the verdict, and why, when the two are close: the runner-up
// adds significantly beyond the verdict, or else the next candidate of another family in the
// ranking is not separated from the verdict by prediction.
std::optional<std::size_t> PairPartner(const VerdictInputs& in, const Ranking& ranking, std::size_t v,
                                       const RunnerUp& runner, std::string* why) {
  const auto& results = in.scored.results;
  if (runner.k && runner.p < in.scored.alpha_each) {
    *why = "it adds significantly beyond the verdict";
    return runner.k;
  }
  for (auto k : ranking.order)
    if (results[k].significant && results[k].family != results[v].family) {
      if (Beats(in.scored, v, k)) return std::nullopt;
      *why = "the ranking does not separate it from the verdict by prediction";
      return k;
    }
  return std::nullopt;
}

// When a pair is named (verdict and `also`, fitted together as out->pair), another pair of
// families (one may be the verdict's) that explains and predicts better (BetterJointPair)
// replaces it: its lead becomes the verdict, its other `also`. Returns the verdict's candidate.
std::size_t SearchPair(const VerdictInputs& in, const Ranking& ranking, std::size_t v,
                       const std::optional<std::size_t>& partner, DiagnosisResult* out) {
  if (!partner || !out->verdict.also || !out->pair || out->pair->families.size() != 2 ||
      out->pair->families[1] != *out->verdict.also)
    return v;
  auto searched = BetterJointPair(in, ranking, *out->pair, v, *partner);
  if (!searched) return v;
  out->verdict.indistinguishable_from.clear();
  NameVerdict(in, ranking, searched->lead, out);
  AddAliases(in, searched->lead, out);
  out->verdict.also = in.scored.results[searched->other].family;
  std::erase(out->verdict.indistinguishable_from, *out->verdict.also);
  out->pair = std::move(searched->fit);
  return searched->lead;
}

// The candidate whose family is `also`: the pair's second when the pair is it, else the runner-up's.
std::optional<std::size_t> AlsoCandidate(const VerdictInputs& in, const DiagnosisResult& out, const RunnerUp& runner) {
  if (!out.verdict.also) return std::nullopt;
  const auto& results = in.scored.results;
  if (out.pair && out.pair->families.size() == 2 && out.pair->families[1] == *out.verdict.also)
    for (std::size_t k = 0; k < results.size(); ++k)
      if (results[k].name == out.pair->names[1]) return k;
  return runner.k;
}

// AddAliases's test one step on, for `also` (candidate a) beside the verdict's candidate v: a
// family one of whose candidates, seen off the base and v, reproduces >= alias_capture of a's
// fitted signature off them. Each projection is of every row: on several threads from
// kParallelMinPoints points.
void AddAlsoAliases(const VerdictInputs& in, std::size_t v, std::size_t a, DiagnosisResult* out) {
  const auto& results = in.scored.results;
  const Eigen::MatrixXd& U0 = in.fit.basis.U;
  const Eigen::MatrixXd& Uv = in.scored.bases[v].U;
  Eigen::MatrixXd Q(U0.rows(), U0.cols() + Uv.cols());
  Q << U0, Uv;
  auto off_verdict = [&](std::size_t k) {
    return ProjectCandidate(ColumnsOf(in.catalogue.candidates[k]), Q, in.options.absorbed_tolerance).U;
  };
  const Eigen::MatrixXd Ua = off_verdict(a);
  const Eigen::VectorXd s_a = Ua * (Ua.transpose() * in.gap.r);
  const double e_a = s_a.squaredNorm();
  auto& ind = out->verdict.also_indistinguishable_from;
  ind.clear();
  if (e_a <= 0) return;
  std::vector<std::size_t> ks;
  for (std::size_t k = 0; k < results.size(); ++k)
    if (results[k].observable && results[k].family != results[v].family && results[k].family != results[a].family)
      ks.push_back(k);
  std::vector<double> captured(ks.size(), 0.0);
  ParallelForEach(ks.size(), static_cast<std::size_t>(in.gap.r.size()) >= kParallelMinPoints,
                  [&](std::size_t i) { captured[i] = (off_verdict(ks[i]).transpose() * s_a).squaredNorm() / e_a; });
  for (std::size_t i = 0; i < ks.size(); ++i)
    if (captured[i] >= in.options.alias_capture && std::find(ind.begin(), ind.end(), results[ks[i]].family) == ind.end())
      ind.push_back(results[ks[i]].family);
  std::sort(ind.begin(), ind.end());
}

}  // namespace

// Ranking of the significant candidates, pairwise (candidates hold out different features, so
// their cv figures are not comparable as they stand). A beats B when A's held-out squared
// residuals are smaller than B's on the features both hold out, by more than twice the standard
// error of the sum of the per-feature differences d_g = ss_A,g - ss_B,g (paired over the m common
// features: |sum d| > 2 sqrt(m) sd(d)); by PRESS over every point (the smaller wins) when either
// is judged by PRESS (cv_method) or they share fewer than 3 held-out features: two candidates are
// always compared on the same kind of figure. Both feature-tested means both hold out exactly
// the base's features, so the common set is the base's. When that does not decide (the data
// cannot tell them apart by prediction), the smaller delta BIC wins.
bool Beats(const ScoredCandidates& scored, std::size_t a, std::size_t b) {
  const CvTrace &ta = scored.traces[a], &tb = scored.traces[b];
  double sum = 0.0, sum2 = 0.0;
  int m = 0;
  if (!ta.held_out.empty() && !tb.held_out.empty()) {
    for (std::size_t g = 0; g < ta.held_out.size(); ++g) {
      if (!ta.held_out[g] || !tb.held_out[g]) continue;
      const double d = ta.ss_by_feature[g] - tb.ss_by_feature[g];
      sum += d;
      sum2 += d * d;
      ++m;
    }
  }
  if (m >= 3) {
    const double mean = sum / m;
    const double var = std::max(0.0, (sum2 - m * mean * mean) / (m - 1));
    const double se_sum = std::sqrt(var * m);
    if (sum < -2.0 * se_sum) return true;
    if (sum > 2.0 * se_sum) return false;
  } else if (ta.press_ss < tb.press_ss) {
    return true;
  } else if (ta.press_ss > tb.press_ss) {
    return false;
  }
  return scored.results[a].delta_bic < scored.results[b].delta_bic;
}

std::pair<double, double> FBeyond(const VerdictInputs& in, std::size_t j, std::size_t k) {
  return FBeyondEach(in, {{j, k}}).front();
}

Ranking RankCandidates(const ScoredCandidates& scored) {
  const auto& results = scored.results;
  Ranking ranking;
  ranking.order.resize(results.size());
  for (std::size_t k = 0; k < ranking.order.size(); ++k) ranking.order[k] = k;
  std::vector<int> wins(results.size(), 0);
  for (std::size_t a = 0; a < results.size(); ++a)
    for (std::size_t b = 0; b < results.size(); ++b)
      if (a != b && results[a].significant && results[b].significant && Beats(scored, a, b)) ++wins[a];
  auto rank_key = [&](std::size_t k) {
    const auto& c = results[k];
    const double ratio = c.cv_rms_before_um > 0 ? c.cv_rms_after_um / c.cv_rms_before_um : 1.0;
    return std::make_tuple(c.significant ? 0 : (c.observable ? 1 : 2), -wins[k], ratio);
  };
  std::stable_sort(ranking.order.begin(), ranking.order.end(),
                   [&](std::size_t a, std::size_t b) { return rank_key(a) < rank_key(b); });
  for (auto k : ranking.order) ranking.best_of_family.try_emplace(results[k].family, k);
  return ranking;
}

FinalModel DecideVerdict(const VerdictInputs& in, const Ranking& ranking, DiagnosisResult* out) {
  const auto& results = in.scored.results;
  const double reference_ss = in.fit.reference_var_um2.sum();
  if (ranking.order.empty() || !results[ranking.order.front()].significant)
    return {in.gap.ssr, in.fit.basis.rank, reference_ss, std::nullopt};
  const std::size_t v = ranking.order.front();
  NameVerdict(in, ranking, v, out);
  AddAliases(in, v, out);
  const RunnerUp runner = FindRunnerUp(in, v, out->verdict);
  if (runner.k && runner.p < in.scored.alpha_each) out->verdict.also = results[*runner.k].family;
  std::string why;
  const auto partner = PairPartner(in, ranking, v, runner, &why);
  if (partner) out->pair = FitPair(in, v, *partner, why);
  if (out->verdict.also && !results[*runner.k].significant &&
      !PairPredictsBetter(out->pair, results[v], PairCvMeanSquareRatio(in, runner)))
    out->verdict.also.reset();
  const std::size_t lead = SearchPair(in, ranking, v, partner, out);
  NameIndistinguishableCandidates(in, ranking, lead, out);
  if (const auto a = AlsoCandidate(in, *out, runner)) AddAlsoAliases(in, lead, *a, out);
  const double n = static_cast<double>(in.gap.r.size());
  // The reference's share along the verdict's directions is fitted.
  const double reference_in = ReferenceVarianceAlong(in.fit, in.scored.bases[lead].U);
  return {results[lead].rms_after_um * results[lead].rms_after_um * n, in.fit.basis.rank + results[lead].rank,
          std::max(0.0, reference_ss - reference_in), lead};
}

void ReportCandidates(const VerdictInputs& in, const Ranking& ranking, const std::optional<std::size_t>& verdict,
                      DiagnosisResult* out) {
  if (verdict) out->candidates.push_back(in.scored.results[*verdict]);
  for (auto k : ranking.order)
    if (k != verdict) out->candidates.push_back(in.scored.results[k]);
  // Families without any observable candidate.
  for (const auto& [family, reason] : in.catalogue.not_applicable) out->unobservable.push_back({family, reason});
  std::map<std::string, bool> family_observable;
  for (const auto& c : out->candidates) family_observable[c.family] = family_observable[c.family] || c.observable;
  for (const auto& [family, obsv] : family_observable)
    if (!obsv)
      out->unobservable.push_back({family, "every candidate of this family is absorbed by the base model and the "
                                           "re-alignment on this piece and plan (or never acts on the measured points)"});
  // Families whose every candidate keeps only a small share of a typical signature outside the
  // base model (RMS sine of the principal angles below weak_visibility): observable in principle,
  // but an effect must be about 1 / share times the noise before it shows. Single cone: drift
  // (8 %) and linear positioning (4 %), which the validation finds unobservable in 59 and 60 of 60
  // trials; the turning piece's least visible family, drift, keeps 26 %.
  std::map<std::string, double> family_share;
  for (const auto& c : out->candidates)
    if (c.observable) family_share[c.family] = std::max(family_share[c.family], c.typical_visible_share);
  for (const auto& [family, share] : family_share)
    if (share < in.options.weak_visibility) out->weakly_observable.push_back({family, share});
}

namespace {

// A gap at least 15 % above the noise RMS (an unmodelled signature of RMS 0.57 sigma) is worth
// naming even when the test is significant for less.
constexpr double kExcessRatio = 1.15;

// p-value of "the base gap is noise of the neighbour sigma": F = (SSR / dof) / sigma^2 against
// the MAD's effective degrees of freedom (0.37 n); SSR in one hit's noise (BaseGap::noise_ssr).
// With a reference's leftover uncertainty (its factor, off every fitted column) SSR's law is
// SatterthwaiteLaw's of noise on dof and that factor: F = SSR / its mean on its d and the mean's
// own (EstimatedMeanDof); pooled cells there by their mean noise scale^2.
double ExcessPValue(const VerdictInputs& in, double sigma_um) {
  const auto n = static_cast<double>(in.gap.r.size());
  const double dof = n - in.fit.basis.rank;
  if (sigma_um <= 0 || dof <= 0) return 1.0;
  const Eigen::MatrixXd& R = in.fit.reference_remaining_um;
  if (R.cols() == 0) return FUpperTail((in.gap.noise_ssr / dof) / (sigma_um * sigma_um), dof, 0.37 * n);
  const double s2 = sigma_um * sigma_um * in.gap.mean_noise_scale2;
  const ChiSquareLaw law = SatterthwaiteLaw(static_cast<int>(dof), s2, R);
  return FUpperTail(in.gap.ssr / law.mean_um2, law.dof, EstimatedMeanDof(law, static_cast<int>(dof), s2, 0.37 * n));
}

std::string DefectName(const LocalDefect& d) {
  return fmt::format("local defect on {} ({} points, peak {:+.2f} um over {:.1f} mm)", d.feature, d.n_points, d.peak_um,
                     2.0 * d.extent_mm);
}

// The observable candidates that explain some of the gap (cross-validated shrink > 0), best first, at most 3.
std::vector<std::string> PartialCandidates(const DiagnosisResult& out) {
  std::vector<const CandidateResult*> c;
  for (const auto& cand : out.candidates)
    if (cand.observable && cand.cv_shrink_pct > 0) c.push_back(&cand);
  std::stable_sort(c.begin(), c.end(), [](auto* a, auto* b) { return a->cv_shrink_pct > b->cv_shrink_pct; });
  std::vector<std::string> names;
  for (std::size_t k = 0; k < c.size() && k < 3; ++k)
    names.push_back(fmt::format("{} ({}: cv shrink {:.0f} %)", c[k]->family, c[k]->name, c[k]->cv_shrink_pct));
  return names;
}

}  // namespace

void CompleteVerdict(const VerdictInputs& in, DiagnosisResult* out) {
  out->excess_p_value = ExcessPValue(in, out->neighbour_sigma_um);
  Verdict& v = out->verdict;
  if (v.family != "none") {
    v.families = {v.family};
    if (v.also) v.families.push_back(*v.also);
    if (!out->local_defects.empty()) v.families.push_back("local_defect");
    return;
  }
  // The gap is that of the points kept: a local defect's points are left out, so what still stands
  // out lies elsewhere (a bent part flags patches and more).
  const double n = static_cast<double>(in.gap.r.size());
  const double rms_beyond_reference_um =
      std::sqrt(SsrBeyondReference(in.fit, in.gap.ssr) / n / in.gap.mean_noise_scale2);
  const bool excess =
      out->excess_p_value < in.options.alpha && rms_beyond_reference_um > kExcessRatio * out->neighbour_sigma_um;
  if (!out->local_defects.empty() && out->standing_out.empty() && !excess) {
    v.family = "local_defect";
    v.name = DefectName(out->local_defects.front());
    for (std::size_t k = 1; k < out->local_defects.size(); ++k) v.name += "; " + DefectName(out->local_defects[k]);
    v.families = {v.family};
    return;
  }
  if (out->standing_out.empty() && !excess) return;
  v.family = "unexplained";
  v.name = out->standing_out.empty()
               ? fmt::format("a gap of {:.2f} um RMS over noise of {:.2f} um that no candidate explains", out->rms_um,
                             out->neighbour_sigma_um)
               : "a gap no candidate explains, standing out at " + fmt::format("{}", fmt::join(out->standing_out, ", "));
  v.families = {v.family};
  if (!out->local_defects.empty()) v.families.push_back("local_defect");
  v.partial = PartialCandidates(*out);
}

}  // namespace tpcal::pipeline::diagnosis_internal
