// The verdict and its runner-up fitted jointly (diagnosis.h, PairFit): how much more the pair
// explains than the verdict alone, cross-validated as the two candidates were. Internal to the
// diagnosis library.
#pragma once

#include <cstddef>
#include <string>

#include "pipeline/diagnosis/diagnosis.h"
#include "pipeline/diagnosis/diagnosis_verdict.h"

namespace tpcal::pipeline::diagnosis_internal {

// Candidates v (the verdict) and k (the runner-up) fitted together with the base; `why` names the
// closeness test that selected the pair.
PairFit FitPair(const VerdictInputs& in, std::size_t v, std::size_t k, const std::string& why);

}  // namespace tpcal::pipeline::diagnosis_internal
