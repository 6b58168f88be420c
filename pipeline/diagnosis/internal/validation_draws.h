// The random draws of the diagnosis validation studies (diagnosis_validate.cc and
// validation_injections.cc share one generator sequence, so they share these definitions).
#pragma once

#include <random>

namespace tpcal::pipeline::internal {

// An integer in [0, n).
inline int Pick(std::mt19937_64& rng, int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng); }
// A double in [a, b).
inline double Uniform(std::mt19937_64& rng, double a, double b) {
  return std::uniform_real_distribution<double>(a, b)(rng);
}

}  // namespace tpcal::pipeline::internal
