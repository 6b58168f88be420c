#include "core/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>

namespace tpcal {

std::size_t HardwareThreads() {
  return static_cast<std::size_t>(std::max(1, tbb::this_task_arena::max_concurrency()));
}

bool ParallelChunks(std::size_t n, std::size_t min_chunk, const std::function<bool(std::size_t, std::size_t)>& fn) {
  const std::size_t grain = std::max<std::size_t>(1, min_chunk);
  if (n <= grain || HardwareThreads() <= 1) return fn(0, n);
  std::atomic<bool> ok{true};
  tbb::this_task_arena::isolate([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, grain), [&](const tbb::blocked_range<std::size_t>& r) {
      if (!fn(r.begin(), r.end())) ok.store(false, std::memory_order_relaxed);
    });
  });
  return ok.load();
}

void ParallelForEach(std::size_t n, bool parallel, const std::function<void(std::size_t)>& fn) {
  if (!parallel || n <= 1 || HardwareThreads() <= 1) {
    for (std::size_t i = 0; i < n; ++i) fn(i);
    return;
  }
  tbb::this_task_arena::isolate([&] {
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, n, 1),
        [&](const tbb::blocked_range<std::size_t>& r) {
          for (std::size_t i = r.begin(); i < r.end(); ++i) fn(i);
        },
        tbb::simple_partitioner());
  });
}

void WithThreadLimit(int threads, const std::function<void()>& fn) {
  if (threads <= 0) return fn();
  tbb::task_arena arena(threads);
  arena.execute(fn);
}

}  // namespace tpcal
