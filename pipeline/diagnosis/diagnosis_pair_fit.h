// The verdict and its runner-up fitted jointly (diagnosis.h, PairFit): how much more the pair
// explains than the verdict alone, cross-validated as the two candidates were. Internal to the
// diagnosis library.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <utility>

#include "pipeline/diagnosis/diagnosis.h"
#include "pipeline/diagnosis/diagnosis_verdict.h"

namespace tpcal::pipeline::diagnosis_internal {

// Candidates v (the verdict) and k (the runner-up) fitted together with the base; `why` names the
// closeness test that selected the pair.
PairFit FitPair(const VerdictInputs& in, std::size_t v, std::size_t k, const std::string& why);

// Forward selection (the verdict, then what adds most beyond it) misses a pair whose sum looks
// most like a third family. Of every two observable candidates of two families (each family's
// kBestPerFamily that explain most alone), the pair with the smallest joint BIC (n log SSR + rank
// log n) when its families differ from `current`'s (one may be shared), explains more than it in
// sample (BIC) and predicts better (FitPair's held-out RMS lower, same method), its lead
// significant alone and its other adding significantly beyond the lead (F, alpha_each):
// {lead, other} with its fit, lead the one whose family ranks first alone (`ranking`: the
// verdict's family stays the verdict when the pair holds it). Else nullopt.
struct SearchedPair {
  std::size_t lead = 0, other = 0;
  PairFit fit;
};
std::optional<SearchedPair> BetterJointPair(const VerdictInputs& in, const Ranking& ranking, const PairFit& current,
                                            std::size_t v, std::size_t k);

}  // namespace tpcal::pipeline::diagnosis_internal
