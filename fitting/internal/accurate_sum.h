// Internal to tpcal::fitting: sums whose rounding error does not grow with the point count.
// Naive summation of n terms has error ~ n eps; CMM scans reach 10^6 points far from the
// origin, so every fitter accumulates through BlockSums (error ~ (kSumBlock + 2) eps per
// sum) at the cost of one compensated add per block, which keeps passes memory-bound.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

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

// N accurate sums over items 0..n-1. `terms(i)` returns item i's N terms as a
// std::array<double, N> (by value: the sums then stay in registers; an accumulator passed by
// reference to a lambda that also writes through a pointer is kept in memory by the
// compiler, several times slower). Items are summed naively in blocks of kSumBlock; the
// block totals are combined with Neumaier compensation.
template <std::size_t N, typename Terms>
std::array<double, N> BlockSums(std::size_t n, Terms&& terms) {
  std::array<NeumaierSum, N> total{};
  for (std::size_t b = 0; b < n; b += kSumBlock) {
    // Two interleaved partial sums per term: the adds of consecutive items do not wait on
    // each other (the loop is otherwise bound by the add latency, not by memory).
    double acc0[N] = {}, acc1[N] = {};
    const std::size_t e = std::min(n, b + kSumBlock);
    std::size_t i = b;
    for (; i + 1 < e; i += 2) {
      const std::array<double, N> t0 = terms(i);
      const std::array<double, N> t1 = terms(i + 1);
      for (std::size_t k = 0; k < N; ++k) {
        acc0[k] += t0[k];
        acc1[k] += t1[k];
      }
    }
    if (i < e) {
      const std::array<double, N> t0 = terms(i);
      for (std::size_t k = 0; k < N; ++k) acc0[k] += t0[k];
    }
    for (std::size_t k = 0; k < N; ++k) total[k].Add(acc0[k] + acc1[k]);
  }
  std::array<double, N> out{};
  for (std::size_t k = 0; k < N; ++k) out[k] = total[k].Total();
  return out;
}

// Sum of squares (compensated as BlockSums), minimum and maximum of value(i), i < n; each
// value is also written to out[i] if out is not null.
struct ValueSums {
  double sum_sq = 0.0;
  double min = std::numeric_limits<double>::infinity();
  double max = -std::numeric_limits<double>::infinity();
};
template <typename Value>
ValueSums SumValues(std::size_t n, Value&& value, double* __restrict out) {
  NeumaierSum total;
  ValueSums s;
  for (std::size_t b = 0; b < n; b += kSumBlock) {
    const std::size_t e = std::min(n, b + kSumBlock);
    // Four interleaved partial sums, minima and maxima (latency, as in BlockSums).
    double acc[4] = {}, lo[4] = {s.min, s.min, s.min, s.min}, hi[4] = {s.max, s.max, s.max, s.max};
    std::size_t i = b;
    for (; i + 3 < e; i += 4) {
      for (std::size_t l = 0; l < 4; ++l) {
        const double v = value(i + l);
        acc[l] += v * v;
        lo[l] = std::min(lo[l], v);
        hi[l] = std::max(hi[l], v);
        if (out != nullptr) out[i + l] = v;
      }
    }
    for (; i < e; ++i) {
      const double v = value(i);
      acc[0] += v * v;
      lo[0] = std::min(lo[0], v);
      hi[0] = std::max(hi[0], v);
      if (out != nullptr) out[i] = v;
    }
    total.Add((acc[0] + acc[1]) + (acc[2] + acc[3]));
    s.min = std::min(std::min(lo[0], lo[1]), std::min(lo[2], lo[3]));
    s.max = std::max(std::max(hi[0], hi[1]), std::max(hi[2], hi[3]));
  }
  s.sum_sq = total.Total();
  return s;
}

// A power of two near `x` > 0: scaling by it is exact in binary floating point, so centred
// and scaled coordinates carry no extra rounding.
inline double PowerOfTwoNear(double x) { return std::ldexp(1.0, std::ilogb(x)); }

}  // namespace tpcal::fitting::internal
