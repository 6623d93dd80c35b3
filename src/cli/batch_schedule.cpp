#include "cli/batch_schedule.h"

#include <atomic>
#include <exception>
#include <mutex>
#include <thread>

namespace ahd::cli {

void run_batch_plan(const BatchPlan& plan, const std::function<void(size_t index, int threads)>& convert) {
  std::atomic<size_t> next{0};
  std::atomic<bool> stop{false};
  std::exception_ptr first;
  std::mutex first_lock;
  auto fail = [&]() {
    std::lock_guard<std::mutex> l(first_lock);
    if (!first) first = std::current_exception();
    stop = true;
  };
  auto worker = [&]() {
    while (!stop) {
      const size_t k = next.fetch_add(1);
      if (k >= plan.small.size()) return;
      try {
        convert(plan.small[k], 1);
      } catch (...) {
        fail();
      }
    }
  };
  std::vector<std::thread> pool;
  for (int j = 0; j < plan.jobs && !plan.small.empty(); ++j) pool.emplace_back(worker);
  for (std::thread& t : pool) t.join();
  for (size_t k = 0; k < plan.large.size() && !stop; ++k) {
    try {
      convert(plan.large[k], plan.threads);
    } catch (...) {
      fail();
    }
  }
  if (first) std::rethrow_exception(first);
}

}  // namespace ahd::cli
