// The one parallel loop of tpcal, on oneTBB's shared pool (Debian libtbb). Every index is handled
// by exactly one call, so results written per index do not depend on the thread count or the
// schedule. Loops nest: an inner loop shares the pool of the outer one (no N x cores threads), and
// a thread waiting on an inner loop runs only that loop's tasks (isolation: no re-entry).
#pragma once

#include <cstddef>
#include <functional>

namespace tpcal {

// The point count from which a loop over points (or over work that grows with them) runs on several
// threads; below it the loop costs less than its tasks (a diagnosis candidate of the 352-point
// sample: ~0.3 ms; a feature's kd-tree at 10^5 points: 0.1 s on one thread).
constexpr std::size_t kParallelMinPoints = 20000;

// Threads the loops below may use here: the innermost ThreadLimit in force, else the cores.
std::size_t HardwareThreads();

// Runs fn(begin, end) over [0, n) in contiguous chunks of at least `min_chunk` indices
// (n <= min_chunk runs inline on the calling thread). Returns false if any call returned false
// (the other chunks still run to their end). fn must not throw.
bool ParallelChunks(std::size_t n, std::size_t min_chunk, const std::function<bool(std::size_t, std::size_t)>& fn);

// Runs fn(i) for every i in [0, n), tasks of unequal cost handed out one at a time (`parallel`
// false: in order on the calling thread). fn must not throw.
void ParallelForEach(std::size_t n, bool parallel, const std::function<void(std::size_t)>& fn);

// Runs fn() with every loop it starts (nested ones included) on at most `threads` threads in all
// (threads <= 0: the cores). Used by `run --batch -j N`.
void WithThreadLimit(int threads, const std::function<void()>& fn);

}  // namespace tpcal
