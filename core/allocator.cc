#include "core/allocator.h"

#include <cstdlib>  // defines __GLIBC__ with glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace tpcal {

void KeepFreedMemoryForReuse() {
#if defined(__GLIBC__)
  (void)mallopt(M_MMAP_MAX, 0);
  (void)mallopt(M_TRIM_THRESHOLD, 2147483647);
  (void)mallopt(M_ARENA_MAX, 1);
#endif
}

}  // namespace tpcal
