// Internal to tpcal::fitting: sums whose rounding error does not grow with the point count.
// Naive summation of n terms has error ~ n eps; CMM scans reach 10^6 points far from the
// origin, so every fitter accumulates through BlockSums (error ~ (kSumBlock + 2) eps per
// sum) at the cost of one compensated add per block, which keeps passes memory-bound.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

namespace tpcal::fitting::internal {

// Neumaier's compensated summation (Kahan's with the |x| > |sum| case handled).
class NeumaierSum {
 public:
  void Add(double x) {
    const double t = sum_ + x;
    comp_ += std::abs(sum_) >= std::abs(x) ? (sum_ - t) + x : (x - t) + sum_;
    sum_ = t;
  }
  double Total() const { return sum_ + comp_; }

 private:
  double sum_ = 0.0;
  double comp_ = 0.0;
};

inline constexpr std::size_t kSumBlock = 256;

// N accurate sums over items 0..n-1. `add_terms(i, acc)` adds item i's N terms into acc
// (a std::array<double, N>&). Items are summed naively in blocks of kSumBlock; the block
// totals are combined with Neumaier compensation.
template <std::size_t N, typename AddTerms>
std::array<double, N> BlockSums(std::size_t n, AddTerms&& add_terms) {
  std::array<NeumaierSum, N> total{};
  for (std::size_t b = 0; b < n; b += kSumBlock) {
    std::array<double, N> acc{};
    const std::size_t e = std::min(n, b + kSumBlock);
    for (std::size_t i = b; i < e; ++i) add_terms(i, acc);
    for (std::size_t k = 0; k < N; ++k) total[k].Add(acc[k]);
  }
  std::array<double, N> out{};
  for (std::size_t k = 0; k < N; ++k) out[k] = total[k].Total();
  return out;
}

// A power of two near `x` > 0: scaling by it is exact in binary floating point, so centred
// and scaled coordinates carry no extra rounding.
inline double PowerOfTwoNear(double x) { return std::ldexp(1.0, std::ilogb(x)); }

}  // namespace tpcal::fitting::internal
