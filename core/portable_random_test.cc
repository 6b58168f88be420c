#include "core/portable_random.h"

#include <gtest/gtest.h>

#include <cmath>

namespace tpcal {
namespace {

// Truth: the engine's 10000th output for the default seed is fixed by the C++ standard
// (9981545732273789042); the draws are pure functions of the engine outputs.
TEST(PortableRandom, EngineIsTheStandardOne) {
  std::mt19937_64 rng;
  rng.discard(9999);
  EXPECT_EQ(rng(), 9981545732273789042ULL);
}

TEST(PortableRandom, UniformUsesTheTop53Bits) {
  std::mt19937_64 a(7), b(7);
  const std::uint64_t x = b();
  EXPECT_EQ(UniformUnit(a), static_cast<double>(x >> 11) / 9007199254740992.0);
  std::mt19937_64 c(7);
  EXPECT_EQ(UniformIn(c, -2.0, 6.0), -2.0 + 8.0 * static_cast<double>(x >> 11) / 9007199254740992.0);
}

// Truth: mean 0 and variance 1. With n = 200000 the standard errors are 1/sqrt(n) = 0.0022 for
// the mean and sqrt(2/n) = 0.0032 for the variance; 5 standard errors each.
TEST(PortableRandom, NormalHasUnitVariance) {
  std::mt19937_64 rng(2026);
  const int n = 200000;
  double sum = 0, sum2 = 0, tail = 0;
  for (int i = 0; i < n; ++i) {
    const double z = StandardNormal(rng);
    sum += z;
    sum2 += z * z;
    tail += std::abs(z) > 1.959964 ? 1 : 0;
  }
  const double mean = sum / n, var = sum2 / n - mean * mean;
  EXPECT_NEAR(mean, 0.0, 5 * 0.0022);
  EXPECT_NEAR(var, 1.0, 5 * 0.0032);
  // P(|z| > 1.96) = 0.05, standard error sqrt(0.05 * 0.95 / n) = 0.00049.
  EXPECT_NEAR(tail / n, 0.05, 5 * 0.00049);
}

}  // namespace
}  // namespace tpcal
