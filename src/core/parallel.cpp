#include "core/parallel.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace ahd {

int resolve_threads(int requested) {
  if (requested > 0) return requested;
  // Asked once: glibc reads /sys for it, and small calls (one block decoded for the error
  // estimate) would otherwise open a file each.
  static const unsigned hw = std::thread::hardware_concurrency();
  return hw == 0 ? 1 : int(hw);
}

void parallel_for(size_t count, int threads, size_t grain, const std::function<void(size_t)>& fn) {
  if (count == 0) return;
  grain = std::max<size_t>(grain, 1);
  const size_t chunks = (count + grain - 1) / grain;
  const int n = int(std::min<size_t>(size_t(resolve_threads(threads)), chunks));
  if (n <= 1) {
    for (size_t i = 0; i < count; ++i) fn(i);
    return;
  }
  std::atomic<size_t> next{0};
  std::exception_ptr first_error;
  std::mutex error_mutex;
  auto worker = [&]() {
    for (;;) {
      const size_t c = next.fetch_add(1);
      if (c >= chunks) return;
      const size_t end = std::min(count, (c + 1) * grain);
      try {
        for (size_t i = c * grain; i < end; ++i) fn(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!first_error) first_error = std::current_exception();
        next = chunks;  // stop handing out work
        return;
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < n; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  if (first_error) std::rethrow_exception(first_error);
}

}  // namespace ahd
