// Allocator tuning for the dense-scan stages, which allocate and free n x k matrices of tens to
// hundreds of MB again and again (per candidate, per Jacobian pass). With glibc's defaults each
// such block is a fresh mapping: a page fault and a page clear per 4 KiB at first touch, and an
// munmap at free. Measured on the 2e6-point pipeline benchmark (2 cores): 3.5 M page faults and
// 28.7 s with the defaults; 1.5 M and 25.5 s with freed blocks kept for reuse; peak RSS 6.4 ->
// 6.5 GB (the process keeps what it freed until it exits).
#pragma once

namespace tpcal {

// glibc: large blocks from the heap instead of their own mappings (M_MMAP_MAX 0), freed memory
// trimmed only beyond 2 GB (M_TRIM_THRESHOLD), one arena (M_ARENA_MAX 1: blocks freed by one
// thread serve the next thread's). Call at the start of main, before any thread starts; a
// no-op with other C libraries (and under sanitizers, whose allocator ignores it).
void KeepFreedMemoryForReuse();

}  // namespace tpcal
