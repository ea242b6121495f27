// The CPU side of an analysis frame on every core (issue #17: 4K × 1000 lights in ≤ 30 s on 16
// cores). parallelFor hands out the indices [0, n) one at a time to analysisThreads() threads; the
// callers keep one partial result per index (a row, a tile) and reduce them in index order, so the
// result is the same bit for bit whatever the thread count (HYBRIDBENCH_THREADS=1 is the serial run).
#pragma once
#include <cstddef>
#include <functional>

namespace hb {

// HYBRIDBENCH_THREADS when set (1..1024; anything else: InputError), else the hardware's threads.
unsigned analysisThreads();

// Calls fn(i) once for every i in [0, n), on up to analysisThreads() threads (the caller's among
// them). An exception thrown by fn is rethrown here after every thread stopped (the first one).
void parallelFor(size_t n, const std::function<void(size_t)>& fn);

}  // namespace hb
