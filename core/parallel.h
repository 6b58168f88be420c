// Data-parallel loops on std::thread (no pool): each index is handled by exactly one call, so
// results written per index do not depend on the thread count or the schedule.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <functional>
#include <thread>
#include <vector>

namespace tpcal {

// Threads used by the loops below: std::thread::hardware_concurrency(), at least 1.
inline std::size_t HardwareThreads() { return std::max(1u, std::thread::hardware_concurrency()); }

// Runs fn(begin, end) over [0, n) in contiguous chunks, one per thread, on up to
// HardwareThreads() threads and no more than one per `min_chunk` indices (small n runs inline).
// Returns false if any call returned false (the other chunks still run to their end).
inline bool ParallelChunks(std::size_t n, std::size_t min_chunk,
                           const std::function<bool(std::size_t, std::size_t)>& fn) {
  const std::size_t threads = std::min<std::size_t>(HardwareThreads(), n / std::max<std::size_t>(1, min_chunk) + 1);
  if (threads <= 1) return fn(0, n);
  std::vector<std::thread> pool;
  std::vector<char> ok(threads, 1);
  const std::size_t chunk = (n + threads - 1) / threads;
  for (std::size_t t = 0; t < threads; ++t) {
    const std::size_t b = t * chunk, e = std::min(n, b + chunk);
    pool.emplace_back([&, t, b, e] { ok[t] = (b >= e || fn(b, e)) ? 1 : 0; });
  }
  for (auto& th : pool) th.join();
  return std::all_of(ok.begin(), ok.end(), [](char c) { return c != 0; });
}

// Runs fn(i) for every i in [0, n), tasks of unequal cost handed out one at a time to up to
// HardwareThreads() threads (`parallel` false: in order on the calling thread). fn must not throw.
inline void ParallelForEach(std::size_t n, bool parallel, const std::function<void(std::size_t)>& fn) {
  const std::size_t threads = parallel ? std::min(HardwareThreads(), n) : 1;
  if (threads <= 1) {
    for (std::size_t i = 0; i < n; ++i) fn(i);
    return;
  }
  std::atomic<std::size_t> next{0};
  std::vector<std::thread> pool;
  for (std::size_t t = 0; t < threads; ++t)
    pool.emplace_back([&] {
      for (std::size_t i = next++; i < n; i = next++) fn(i);
    });
  for (auto& th : pool) th.join();
}

}  // namespace tpcal
