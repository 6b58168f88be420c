#include "core/allocator.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace tpcal {
namespace {

// Truth: with the tuning, a 64 MB block (far above glibc's default mmap threshold of 128 KiB to
// 32 MiB) is carved from the heap, not given its own mapping (mallinfo2().hblks counts those), so
// freeing it keeps the pages for the next block. Exact counts, no tolerance.
TEST(Allocator, LargeBlocksComeFromTheHeapForReuse) {
#if defined(__SANITIZE_ADDRESS__) || !defined(__GLIBC__)
  GTEST_SKIP() << "the sanitizer's allocator (or a non-glibc one) ignores glibc's tuning";
#else
  KeepFreedMemoryForReuse();
  const std::size_t bytes = std::size_t{64} << 20;
  const int mapped_before = static_cast<int>(mallinfo2().hblks);
  void* p = std::malloc(bytes);
  ASSERT_NE(p, nullptr);
  std::memset(p, 1, bytes);
  EXPECT_EQ(static_cast<int>(mallinfo2().hblks), mapped_before);
  std::free(p);
#endif
}

}  // namespace
}  // namespace tpcal
