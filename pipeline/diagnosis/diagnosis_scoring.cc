#include "pipeline/diagnosis/diagnosis_scoring.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/parallel.h"
#include "pipeline/diagnosis/diagnosis_least_squares.h"

namespace tpcal::pipeline::diagnosis_internal {
namespace {

// Does any feature held out in `cv1` carry the effect (a non-zero column entry)? If not, the
// feature-CV cannot test the candidate (e.g. an effect acting on one feature only, which is then
// not holdable).
bool ReachesHeldOutFeature(const Columns& C, const Projected& b, const GroupCvResult& cv1, const BaseGap& gap) {
  bool reaches = false;
  double largest = 0.0;
  for (const auto& c : C) largest = std::max(largest, c.size() ? c.cwiseAbs().maxCoeff() : 0.0);
  const double row_tol = 1e-12 * std::max(1e-300, largest);
  for (int g = 0; g < gap.feature_cv.n_groups() && !reaches && b.rank > 0 && !C.empty(); ++g) {
    if (!cv1.holdable[static_cast<std::size_t>(g)]) continue;
    for (auto i : gap.feature_cv.rows(g)) {
      for (const auto& c : C)
        if (std::abs(c(i)) > row_tol) {
          reaches = true;
          break;
        }
      if (reaches) break;
    }
  }
  return reaches;
}

// Feature-CV before and after over the features the joint design can hold out, or the PRESS
// figures when the feature-CV cannot test the candidate (cv_method says which, and why).
CvTrace CrossValidate(const Columns& C, const Projected& b, const Eigen::VectorXd& r1, const BaseGap& gap,
                      CandidateResult* cr) {
  const GroupCvResult cv1 = b.rank > 0 ? gap.feature_cv.Evaluate(b.U, r1) : gap.cv;
  CvTrace trace;
  cr->cv_features = CountTrue(cv1.holdable);
  cr->cv_not_held_out = NotHeldOut(gap, cv1.holdable);
  const bool reaches = ReachesHeldOutFeature(C, b, cv1, gap);
  // Does the candidate make a feature unholdable that the base model holds out (its columns
  // there are fixed by that feature's points alone, e.g. a straightness polynomial by the
  // features at the ends of its axis range)? Its feature-CV would then be taken over a
  // different, smaller set than the base's, leaving out exactly the features where it
  // extrapolates worst, and would not be comparable with the other candidates': it is judged
  // by PRESS instead (as a candidate no held-out feature carries), and says so. Holdable sets
  // only shrink when columns are added (interlacing), so equal counts mean equal sets.
  const bool loses_features = CountTrue(cv1.holdable) < CountTrue(gap.cv.holdable);
  trace.press_ss = cr->press_rms_after_um * cr->press_rms_after_um * static_cast<double>(r1.size());
  if (b.rank == 0 || (reaches && !loses_features)) {
    cr->cv_rms_before_um = gap.cv.RmsOver(cv1.holdable);
    cr->cv_rms_after_um = cv1.Rms();
    trace.ss_by_feature = cv1.ss_by_group;
    trace.held_out = cv1.holdable;
  } else {
    cr->cv_method = "leave-one-point-out";
    cr->cv_method_reason = reaches ? "the effect's columns are fixed by features the base model holds out, which it "
                                     "makes unholdable: leave-one-feature-out would compare it on fewer features"
                                   : "no held-out feature carries the effect";
    cr->cv_rms_before_um = cr->press_rms_before_um;
    cr->cv_rms_after_um = cr->press_rms_after_um;
  }
  return trace;
}

// Parameters of the effect (joint fit = fit of the residual on the projected columns), residual
// variance ssr1 / dof1. Returns their values.
Eigen::VectorXd EffectParameters(const CandidateColumns& cc, const Projected& b, const Eigen::VectorXd& r0,
                                 double ssr1, double dof1, CandidateResult* cr) {
  const double s2 = dof1 > 0 ? ssr1 / dof1 : 0.0;
  const Eigen::VectorXd coef = b.rank > 0 ? Eigen::VectorXd(b.B * (b.U.transpose() * r0))
                                          : Eigen::VectorXd(Eigen::VectorXd::Zero(cc.cols()));
  for (Eigen::Index j = 0; j < coef.size(); ++j) {
    const double u = b.rank > 0 ? std::sqrt(s2 * b.B.row(j).squaredNorm()) : 0.0;
    cr->parameters.push_back({cc.parameter_names[static_cast<std::size_t>(j)], cc.units[static_cast<std::size_t>(j)],
                              coef(j), u, b.identifiable[static_cast<std::size_t>(j)]});
  }
  return coef;
}

// Bias the effect was putting into the base coefficients: the base absorbs X0+ (C coef). With
// the effect modelled a base coefficient is X0+ (y - C g): its variance is the base fit's plus
// A Cov(g) A^T, A = X0+ C, Cov(g) = s2 B B^T (X0+ y and g are uncorrelated: g sees only the
// residual's complement), both at the joint fit's residual variance s2.
void BaseShifts(const Columns& C, const Eigen::VectorXd& coef, const Projected& b, double s2, const BaseFit& fit,
                const std::vector<EffectParameter>& base_parameters, CandidateResult* cr) {
  Eigen::VectorXd effect = Eigen::VectorXd::Zero(fit.y.size());
  for (std::size_t j = 0; j < C.size(); ++j) effect += coef(static_cast<Eigen::Index>(j)) * C[j];
  Eigen::VectorXd dcoef, u0, unused;
  std::vector<bool> dident;
  Solve(fit.basis, effect, s2, &dcoef, &u0, &dident);
  Eigen::MatrixXd A(dcoef.size(), static_cast<Eigen::Index>(C.size()));
  for (std::size_t j = 0; j < C.size(); ++j) {
    Eigen::VectorXd aj;
    Solve(fit.basis, C[j], 0.0, &aj, &unused, &dident);
    A.col(static_cast<Eigen::Index>(j)) = aj;
  }
  const Eigen::MatrixXd AB = A * b.B;
  for (int k = 0; k < fit.q_fit; ++k) {
    const auto& bp = base_parameters[static_cast<std::size_t>(k)];
    if (!bp.identifiable || std::abs(dcoef(k)) < 1e-9) continue;  // no number for what the data cannot separate
    const double u_with = std::sqrt(u0(k) * u0(k) + s2 * AB.row(k).squaredNorm());
    cr->base_shift.push_back({bp.name, bp.unit, bp.value, bp.value - dcoef(k), u0(k), u_with});
  }
}

// The F test of a candidate's reduction `q` of the gap (um^2) along its b.rank directions against
// the noise variance `s2` (um^2, on dof2 degrees of freedom) and, when given, the CMM's noise:
// without a reference (Z with no column), F = (q / rank) / s2 on (rank, dof2). With one, the
// reduction also holds the reference's leftover variance along the candidate's directions (Z:
// their share of its factor, rank x r), whose spread a mean taken off would miss: F = q / the
// mean of SatterthwaiteLaw, on its d and the mean's own (EstimatedMeanDof: s2 is its only
// estimated part).
void ReductionTest(const Eigen::MatrixXd& Z, const Projected& b, double q, double s2, double dof2, double noise_um,
                   CandidateResult* cr) {
  const double known2 = noise_um * noise_um;
  if (Z.cols() == 0) {
    cr->f_stat = (q / b.rank) / s2;
    cr->p_value = FUpperTail(cr->f_stat, b.rank, dof2);
    // With a known CMM noise the reduction must also stand out against it (chi-square with rank
    // degrees of freedom): on noise-free data the F ratio of rounding and linearisation residuals
    // is significant for any candidate.
    if (noise_um > 0) cr->p_value = std::max(cr->p_value, FUpperTail((q / b.rank) / known2, b.rank, 1e12));
    return;
  }
  const ChiSquareLaw law = SatterthwaiteLaw(b.rank, s2, Z);
  cr->f_stat = q / law.mean_um2;
  cr->p_value = FUpperTail(cr->f_stat, law.dof, EstimatedMeanDof(law, b.rank, s2, dof2));
  if (noise_um > 0) {
    const ChiSquareLaw known = SatterthwaiteLaw(b.rank, known2, Z);
    cr->p_value = std::max(cr->p_value, FUpperTail(q / known.mean_um2, known.dof, 1e12));
  }
}

// One candidate's scores; its projection and CV trace in *b and *trace.
CandidateResult ScoreCandidate(const CandidateColumns& cc, const BaseFit& fit, const BaseGap& gap,
                               const std::vector<EffectParameter>& base_parameters, const DiagnosisOptions& options,
                               Projected* b_out, CvTrace* trace) {
  const Eigen::VectorXd& r0 = gap.r;
  const auto n = r0.size();
  CandidateResult cr;
  cr.family = cc.family;
  cr.name = cc.name;
  cr.n_columns = static_cast<int>(cc.cols());
  const Columns C = ColumnsOf(cc);
  Projected b = ProjectCandidate(C, fit.basis.U, options.absorbed_tolerance);
  cr.rank = b.rank;
  cr.observable = b.rank > 0;
  cr.visible_share = b.max_sine;
  cr.typical_visible_share = b.rms_sine;
  cr.press_rms_before_um = gap.press_rms_um;
  const Eigen::VectorXd fitted = b.U * (b.U.transpose() * r0);
  const Eigen::VectorXd r1 = r0 - fitted;
  const double ssr1 = r1.squaredNorm();
  const double dof1 = static_cast<double>(n - fit.basis.rank - b.rank);
  cr.rms_after_um = Rms(r1);
  cr.max_abs_after_um = r1.size() ? r1.cwiseAbs().maxCoeff() : 0.0;
  cr.shrink_pct = gap.rms_um > 0 ? 100.0 * (1.0 - cr.rms_after_um / gap.rms_um) : 0.0;
  cr.press_rms_after_um = Rms(Press(r1, gap.h + RowSquaredNorms(b.U)));
  *trace = CrossValidate(C, b, r1, gap, &cr);
  cr.cv_shrink_pct = cr.cv_rms_before_um > 0 ? 100.0 * (1.0 - cr.cv_rms_after_um / cr.cv_rms_before_um) : 0.0;
  // What a reference's own uncertainty adds to ssr1 (its variance off the candidate's new
  // directions) is taken off it; along them it adds to the reduction's law (ReductionTest).
  // When ssr1 leaves nothing beyond it for the noise, p stays 1 (nothing to test against).
  const Eigen::MatrixXd Z = ReferenceShareAlong(fit, b.U);
  const double ref_out = std::max(0.0, fit.reference_var_um2.sum() - Z.squaredNorm());
  if (b.rank > 0 && dof1 > 0 && ssr1 > ref_out) {
    ReductionTest(Z, b, gap.ssr - ssr1, (ssr1 - ref_out) / dof1, dof1, options.noise_um, &cr);
    cr.delta_bic = static_cast<double>(n) * std::log(ssr1 / gap.ssr) + b.rank * std::log(static_cast<double>(n));
  }
  const Eigen::VectorXd coef = EffectParameters(cc, b, r0, ssr1, dof1, &cr);
  if (fit.q_fit > 0 && b.rank > 0) BaseShifts(C, coef, b, dof1 > 0 ? ssr1 / dof1 : 0.0, fit, base_parameters, &cr);
  *b_out = std::move(b);
  return cr;
}

}  // namespace

ScoredCandidates ScoreCandidates(const CandidateCatalogue& catalogue, const BaseFit& fit, const BaseGap& gap,
                                 const std::vector<EffectParameter>& base_parameters, const DiagnosisOptions& options) {
  const std::size_t n_candidates = catalogue.candidates.size();
  ScoredCandidates s;
  s.bases.resize(n_candidates);
  s.traces.resize(n_candidates);
  s.results.resize(n_candidates);
  // Candidates are independent: each writes its own slot.
  ParallelForEach(n_candidates, static_cast<std::size_t>(gap.r.size()) >= kParallelMinPoints, [&](std::size_t ci) {
    s.results[ci] = ScoreCandidate(catalogue.candidates[ci], fit, gap, base_parameters, options, &s.bases[ci],
                                   &s.traces[ci]);
  });
  s.alpha_each = options.alpha / std::max<std::size_t>(1, s.results.size());
  for (auto& cr : s.results)
    cr.significant = cr.observable && cr.p_value < s.alpha_each && cr.cv_rms_after_um < cr.cv_rms_before_um;
  return s;
}

}  // namespace tpcal::pipeline::diagnosis_internal
