#include "pipeline/io/large_alloc.h"

#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>

namespace tpcal::pipeline {

void AdviseHugePages(const void* p, std::size_t bytes) {
  constexpr std::size_t kMinBytes = std::size_t{4} << 20;
  if (p == nullptr || bytes < kMinBytes) return;
  const std::uintptr_t page = static_cast<std::uintptr_t>(::sysconf(_SC_PAGESIZE));
  const std::uintptr_t begin = (reinterpret_cast<std::uintptr_t>(p) + page - 1) / page * page;
  const std::uintptr_t end = (reinterpret_cast<std::uintptr_t>(p) + bytes) / page * page;
  if (end <= begin) return;
#ifdef MADV_HUGEPAGE
  (void)::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#endif
}

}  // namespace tpcal::pipeline
