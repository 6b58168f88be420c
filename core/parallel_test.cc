#include "core/parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <thread>
#include <vector>

namespace tpcal {
namespace {

// Truth: every index is visited exactly once, whatever the chunking.
TEST(Parallel, ChunksVisitEveryIndexOnce) {
  const std::size_t n = 100003;
  std::vector<int> hits(n, 0);
  EXPECT_TRUE(ParallelChunks(n, 1000, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) ++hits[i];
    return true;
  }));
  for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(hits[i], 1) << i;
}

TEST(Parallel, ChunksReportAFailingChunk) {
  EXPECT_FALSE(ParallelChunks(50000, 100, [](std::size_t b, std::size_t e) { return !(b <= 31337 && 31337 < e); }));
}

TEST(Parallel, ForEachVisitsEveryIndexOnceAndSeriallyInOrder) {
  std::vector<int> hits(257, 0);
  ParallelForEach(hits.size(), true, [&](std::size_t i) { ++hits[i]; });
  for (int h : hits) ASSERT_EQ(h, 1);
  std::vector<std::size_t> order;
  ParallelForEach(5, false, [&](std::size_t i) { order.push_back(i); });
  EXPECT_EQ(order, (std::vector<std::size_t>{0, 1, 2, 3, 4}));
}

// Truth: under a limit of L threads, nested loops (a batch of items, each with its own chunked
// loop) never have more than L bodies running at once. Each body sleeps 1 ms so that any excess
// concurrency would be seen.
TEST(Parallel, NestedLoopsShareOneLimitedPool) {
  for (int limit : {1, 2}) {
    std::atomic<int> active{0}, peak{0};
    auto body = [&] {
      const int now = ++active;
      int p = peak.load();
      while (now > p && !peak.compare_exchange_weak(p, now)) {
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      --active;
    };
    WithThreadLimit(limit, [&] {
      EXPECT_EQ(HardwareThreads(), static_cast<std::size_t>(limit));
      ParallelForEach(8, true, [&](std::size_t) {
        ParallelChunks(64, 4, [&](std::size_t b, std::size_t e) {
          for (std::size_t i = b; i < e; i += 4) body();
          return true;
        });
      });
    });
    EXPECT_LE(peak.load(), limit) << "limit " << limit;
    EXPECT_GE(peak.load(), 1);
  }
}

}  // namespace
}  // namespace tpcal
