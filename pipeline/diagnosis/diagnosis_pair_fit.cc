#include "pipeline/diagnosis/diagnosis_pair_fit.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "pipeline/diagnosis/diagnosis_least_squares.h"
#include "pipeline/diagnosis/diagnosis_projection.h"

namespace tpcal::pipeline::diagnosis_internal {
namespace {

// Leave-one-feature-out over the features the joint design can hold out when both candidates
// were judged that way (and it holds out as many as the base), else leave-one-point-out (PRESS).
void CrossValidatePair(const VerdictInputs& in, std::size_t v, std::size_t k, const Projected& b,
                       const Eigen::VectorXd& r2, PairFit* pf) {
  const BaseGap& gap = in.gap;
  const auto& traces = in.scored.traces;
  const bool by_features = !traces[v].held_out.empty() && !traces[k].held_out.empty();
  const GroupCvResult cv2 = by_features ? gap.feature_cv.Evaluate(b.U, r2) : gap.cv;
  if (by_features && CountTrue(cv2.holdable) == CountTrue(gap.cv.holdable)) {
    pf->cv_rms_before_um = gap.cv.RmsOver(cv2.holdable);
    pf->cv_rms_after_um = cv2.Rms();
  } else {
    pf->cv_method = "leave-one-point-out";
    pf->cv_rms_before_um = gap.press_rms_um;
    pf->cv_rms_after_um = Rms(Press(r2, gap.h + RowSquaredNorms(b.U)));
  }
  pf->cv_shrink_pct = pf->cv_rms_before_um > 0 ? 100.0 * (1.0 - pf->cv_rms_after_um / pf->cv_rms_before_um) : 0.0;
}

// Both effects' parameters from the joint fit (residual r2 after it).
void PairParameters(const CandidateColumns& cv, const CandidateColumns& ck, const Projected& b,
                    const Eigen::VectorXd& r0, const Eigen::VectorXd& r2, int base_rank, PairFit* pf) {
  const double dof2 = static_cast<double>(r0.size() - base_rank - b.rank);
  const double s2 = dof2 > 0 ? r2.squaredNorm() / dof2 : 0.0;
  const Eigen::VectorXd coef = b.B * (b.U.transpose() * r0);
  std::vector<std::pair<std::string, std::string>> names_units;
  for (const auto* c : {&cv, &ck})
    for (std::size_t j = 0; j < c->parameter_names.size(); ++j) names_units.emplace_back(c->parameter_names[j], c->units[j]);
  for (Eigen::Index j = 0; j < coef.size(); ++j) {
    const auto& [name, unit] = names_units[static_cast<std::size_t>(j)];
    pf->parameters.push_back({name, unit, coef(j), std::sqrt(s2 * b.B.row(j).squaredNorm()),
                              b.identifiable[static_cast<std::size_t>(j)]});
  }
}

// Candidates kept per family for the joint search: the family's best few by in-sample fit.
constexpr std::size_t kBestPerFamily = 3;

// The search's pool: per family its kBestPerFamily observable candidates of smallest rms_after.
std::vector<std::size_t> PairPool(const VerdictInputs& in) {
  const auto& results = in.scored.results;
  std::map<std::string, std::vector<std::size_t>> by_family;
  for (std::size_t k = 0; k < results.size(); ++k)
    if (results[k].observable && in.scored.bases[k].rank > 0) by_family[results[k].family].push_back(k);
  std::vector<std::size_t> pool;
  for (auto& [family, ks] : by_family) {
    std::stable_sort(ks.begin(), ks.end(), [&](std::size_t a, std::size_t b) {
      return results[a].rms_after_um < results[b].rms_after_um;
    });
    for (std::size_t i = 0; i < ks.size() && i < kBestPerFamily; ++i) pool.push_back(ks[i]);
  }
  return pool;
}

// The products JointBic needs of a few candidates' directions off the base (ScoredCandidates::
// bases, orthonormal): their Gram matrix and U^T r0 stacked, and |r0 - U U^T r0|^2 of each. One
// n x P product for every pair of the pool, not an n-row SVD per pair (10^5 points: those SVDs
// were a third of the diagnosis, perf).
struct PairProducts {
  std::map<std::size_t, std::pair<Eigen::Index, Eigen::Index>> cols;  // candidate -> first column, rank
  Eigen::MatrixXd gram;
  Eigen::VectorXd ur;
  std::map<std::size_t, double> ssr_alone;
};

PairProducts MakePairProducts(const VerdictInputs& in, const std::vector<std::size_t>& ks) {
  PairProducts p;
  Eigen::Index total = 0;
  for (std::size_t k : ks)
    if (!p.cols.count(k)) p.cols[k] = {total, in.scored.bases[k].U.cols()}, total += in.scored.bases[k].U.cols();
  const Eigen::VectorXd& r0 = in.gap.r;
  Eigen::MatrixXd U(r0.size(), total);
  for (const auto& [k, c] : p.cols) U.middleCols(c.first, c.second) = in.scored.bases[k].U;
  p.gram.setZero(total, total);
  if (total > 0 && U.rows() > 0) p.gram.selfadjointView<Eigen::Lower>().rankUpdate(U.transpose());
  p.gram = p.gram.selfadjointView<Eigen::Lower>();
  p.ur = U.transpose() * r0;
  for (const auto& [k, c] : p.cols) {
    const auto& Uk = in.scored.bases[k].U;
    p.ssr_alone[k] = (r0 - Uk * p.ur.segment(c.first, c.second)).squaredNorm();
  }
  return p;
}

// n log SSR + rank log n of the base, candidate j and candidate k fitted together (the base's
// own terms are common to every pair and left out); SSR floored at 1e-30 of the gap's. From the
// candidates' directions already off the base: k's left off j's are those whose sine to span(j)
// exceeds the absorbed tolerance (singular values of Uk - Uj Uj^T Uk: the square roots of the
// eigenvalues of I - M^T M, M = Uj^T Uk), and what they explain of the residual after j is
// (v^T (Uk^T r0 - M^T Uj^T r0))^2 / s^2 along each such eigenvector v.
double JointBic(const VerdictInputs& in, const PairProducts& p, std::size_t j, std::size_t k) {
  const auto [cj, nj] = p.cols.at(j);
  const auto [ck, nk] = p.cols.at(k);
  const Eigen::MatrixXd M = p.gram.block(cj, ck, nj, nk);
  const Eigen::MatrixXd Gk = p.gram.block(ck, ck, nk, nk) - M.transpose() * M;
  const Eigen::VectorXd along = p.ur.segment(ck, nk) - M.transpose() * p.ur.segment(cj, nj);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig;
  if (nk > 0) eig.compute(Gk);
  const double tol2 = in.options.absorbed_tolerance * in.options.absorbed_tolerance;
  int rank_k = 0;
  double explained = 0.0;
  for (Eigen::Index c = 0; c < nk; ++c)
    if (eig.eigenvalues()(c) > tol2) {
      ++rank_k;
      explained += std::pow(eig.eigenvectors().col(c).dot(along), 2) / eig.eigenvalues()(c);
    }
  const Eigen::VectorXd& r0 = in.gap.r;
  const double ssr = std::max(0.0, p.ssr_alone.at(j) - explained);
  const double n = static_cast<double>(r0.size());
  return n * std::log(std::max(ssr, 1e-30 * r0.squaredNorm())) +
         static_cast<double>(in.scored.bases[j].rank + rank_k) * std::log(n);
}

// Where `family` first appears in the ranking (its best candidate's place).
std::size_t FamilyPlace(const Ranking& ranking, const std::string& family) {
  const auto best = ranking.best_of_family.find(family);
  if (best == ranking.best_of_family.end()) return ranking.order.size();
  return static_cast<std::size_t>(std::find(ranking.order.begin(), ranking.order.end(), best->second) - ranking.order.begin());
}

}  // namespace

std::optional<SearchedPair> BetterJointPair(const VerdictInputs& in, const Ranking& ranking, const PairFit& current,
                                            std::size_t v, std::size_t k) {
  const auto& results = in.scored.results;
  const std::vector<std::size_t> pool = PairPool(in);
  std::vector<std::size_t> needed = pool;
  needed.push_back(v);
  needed.push_back(k);
  const PairProducts products = MakePairProducts(in, needed);
  const double incumbent = JointBic(in, products, v, k);
  double best = incumbent;
  std::optional<std::pair<std::size_t, std::size_t>> found;
  for (std::size_t a = 0; a < pool.size(); ++a)
    for (std::size_t b = a + 1; b < pool.size(); ++b) {
      const std::size_t j = pool[a], m = pool[b];
      if (results[j].family == results[m].family) continue;
      const bool same = (results[j].family == results[v].family && results[m].family == results[k].family) ||
                        (results[j].family == results[k].family && results[m].family == results[v].family);
      if (same) continue;
      const double bic = JointBic(in, products, j, m);
      if (bic < best) best = bic, found = std::make_pair(j, m);
    }
  if (!found) return std::nullopt;
  auto [lead, other] = *found;
  if (FamilyPlace(ranking, results[other].family) < FamilyPlace(ranking, results[lead].family)) std::swap(lead, other);
  // As the named pair's: a significant verdict, and a second effect that adds significantly beyond it.
  if (!results[lead].significant || !(FBeyond(in, other, lead).second < in.scored.alpha_each)) return std::nullopt;
  SearchedPair out{lead, other, FitPair(in, lead, other, "a joint search: it explains the gap better than the "
                                                         "verdict and its runner-up, in sample and held out")};
  if (out.fit.cv_method != current.cv_method || !(out.fit.cv_rms_after_um < current.cv_rms_after_um)) return std::nullopt;
  return out;
}

PairFit FitPair(const VerdictInputs& in, std::size_t v, std::size_t k, const std::string& why) {
  const auto& results = in.scored.results;
  const auto& cv = in.catalogue.candidates[v];
  const auto& ck = in.catalogue.candidates[k];
  const Eigen::VectorXd& r0 = in.gap.r;
  Columns C = ColumnsOf(cv);
  for (const auto& c : ColumnsOf(ck)) C.push_back(c);
  const Projected b = ProjectCandidate(C, in.fit.basis.U, in.options.absorbed_tolerance);
  PairFit pf;
  pf.families = {results[v].family, results[k].family};
  pf.names = {results[v].name, results[k].name};
  pf.why = why;
  pf.rank = b.rank;
  pf.p_value_beyond_verdict = FBeyond(in, k, v).second;
  const Eigen::VectorXd r2 = r0 - b.U * (b.U.transpose() * r0);
  pf.rms_after_um = Rms(r2);
  pf.shrink_pct = in.gap.rms_um > 0 ? 100.0 * (1.0 - pf.rms_after_um / in.gap.rms_um) : 0.0;
  CrossValidatePair(in, v, k, b, r2, &pf);
  PairParameters(cv, ck, b, r0, r2, in.fit.basis.rank, &pf);
  return pf;
}

}  // namespace tpcal::pipeline::diagnosis_internal
