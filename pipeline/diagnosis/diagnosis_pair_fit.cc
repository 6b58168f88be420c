#include "pipeline/diagnosis/diagnosis_pair_fit.h"

#include <cmath>
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

}  // namespace

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
