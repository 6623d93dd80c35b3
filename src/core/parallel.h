// A minimal deterministic parallel-for: work items are independent and each writes only its
// own output, so the result never depends on the thread count or scheduling.
#pragma once
#include <cstddef>
#include <functional>

namespace ahd {

// Number of worker threads to use when the caller asks for `requested` (0 = all hardware threads).
int resolve_threads(int requested);

// Calls fn(i) for every i in [0, count), on up to `threads` threads (0 = all hardware threads),
// handing out contiguous chunks of `grain` items. fn must only write data owned by item i.
// Exceptions thrown by fn are rethrown on the calling thread (the first one wins).
void parallel_for(size_t count, int threads, size_t grain, const std::function<void(size_t)>& fn);

}  // namespace ahd
