// Step 2 of the diagnosis (diagnosis.h): every candidate effect fitted jointly with the base and
// the re-alignment (on the base's residual, its columns projected on the complement of the base
// design) and scored: in-sample shrink, leave-one-feature-out (or leave-one-point-out) RMS before
// and after, F-test and delta BIC against the base, its parameters and the shift it causes in the
// base coefficients. Internal to the diagnosis library.
#pragma once

#include <vector>

#include "pipeline/diagnosis/diagnosis.h"
#include "pipeline/diagnosis/diagnosis_base_fit.h"
#include "pipeline/diagnosis/diagnosis_candidates.h"
#include "pipeline/diagnosis/diagnosis_projection.h"

namespace tpcal::pipeline::diagnosis_internal {

// Per candidate, for the pairwise ranking: feature-CV squared residual per feature and the
// features held out (empty for the PRESS fallback), and the PRESS sum of squares.
struct CvTrace {
  std::vector<double> ss_by_feature;
  std::vector<bool> held_out;
  double press_ss = 0.0;
};

// The candidates of a catalogue scored against the base, in catalogue order.
struct ScoredCandidates {
  std::vector<Projected> bases;  // each candidate's columns projected on the complement of the base
  std::vector<CvTrace> traces;
  std::vector<CandidateResult> results;
  double alpha_each = 0.0;       // per-candidate significance level: alpha / number of candidates
};

// Scores every candidate (on several threads for large point sets; the results do not depend on
// the schedule) and marks the significant ones (Bonferroni: p < alpha / candidates, and the
// cross-validated RMS decreases). `base_parameters`: DiagnosisResult::base_parameters.
ScoredCandidates ScoreCandidates(const CandidateCatalogue& catalogue, const BaseFit& fit, const BaseGap& gap,
                                 const std::vector<EffectParameter>& base_parameters, const DiagnosisOptions& options);

}  // namespace tpcal::pipeline::diagnosis_internal
