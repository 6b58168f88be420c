// Step 3 of the diagnosis (diagnosis.h): the pairwise ranking of the significant candidates, the
// verdict and the families indistinguishable from it, the runner-up and, when the two are close,
// their joint fit (diagnosis_pair_fit.h); then the candidate list of the result with the
// unobservable and weakly observable families. Internal to the diagnosis library.
#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "pipeline/diagnosis/diagnosis.h"
#include "pipeline/diagnosis/diagnosis_base_fit.h"
#include "pipeline/diagnosis/diagnosis_candidates.h"
#include "pipeline/diagnosis/diagnosis_scoring.h"

namespace tpcal::pipeline::diagnosis_internal {

// FBeyond's figures already computed for these inputs, by {j, k}.
using FBeyondMemo = std::map<std::pair<std::size_t, std::size_t>, std::pair<double, double>>;

// What the verdict's tests read: the catalogue, its scores, the base fit and the gap it leaves;
// and the F tests made on them so far (each is a projection of every row, asked for by several
// of the verdict's steps: computed once).
struct VerdictInputs {
  const CandidateCatalogue& catalogue;
  const ScoredCandidates& scored;
  const BaseFit& fit;
  const BaseGap& gap;
  const DiagnosisOptions& options;
  mutable FBeyondMemo f_beyond;
};

// Does candidate a beat candidate b (both significant)? Their held-out squared residuals on the
// features both hold out differ by more than 2 standard errors of the paired sum (>= 3 common
// features), else the smaller PRESS sum; undecided: the smaller delta BIC.
bool Beats(const ScoredCandidates& scored, std::size_t a, std::size_t b);

// F statistic and p-value of candidate j added to base + candidate k ({0, 1} when j adds nothing);
// remembered in in.f_beyond (not safe to call from several threads at once).
std::pair<double, double> FBeyond(const VerdictInputs& in, std::size_t j, std::size_t k);

// The ranking, best first: significant, then observable, then the rest; within each, most
// pairwise wins (Beats), then the smaller cv ratio after / before, then catalogue order. And the
// best candidate of each family (its first in the ranking).
struct Ranking {
  std::vector<std::size_t> order;
  std::map<std::string, std::size_t> best_of_family;
};
Ranking RankCandidates(const ScoredCandidates& scored);

// The model the verdict leaves: its sum of squared residuals (um^2), fitted directions, and the
// part of ssr a reference's own uncertainty is expected to add (um^2; BaseFit::reference_var_um2).
struct FinalModel {
  double ssr = 0.0;
  int dof = 0;
  double reference_ss = 0.0;
  // The verdict's candidate: the ranking's first, or a searched pair's lead (none: no verdict).
  std::optional<std::size_t> verdict;
};

// The verdict, the families indistinguishable from it, `also`, and the pair fit, into `out`.
FinalModel DecideVerdict(const VerdictInputs& in, const Ranking& ranking, DiagnosisResult* out);

// The candidates, the verdict's (FinalModel::verdict) first, then the ranking's order; the
// unobservable and the weakly observable families, into `out`.
void ReportCandidates(const VerdictInputs& in, const Ranking& ranking, const std::optional<std::size_t>& verdict,
                      DiagnosisResult* out);

// After the gap summary: the test of the base gap against the neighbour-difference noise
// (excess_p_value), the verdict's list of families, and where no catalogue candidate is
// significant, local_defect (the screen found a patch) or unexplained (the gap stands out beyond
// noise: a group or harmonic stands out, or the excess test is below alpha with the gap RMS at
// least kExcessRatio x the noise), with the partial candidates; none only when nothing stands out.
void CompleteVerdict(const VerdictInputs& in, DiagnosisResult* out);

}  // namespace tpcal::pipeline::diagnosis_internal
