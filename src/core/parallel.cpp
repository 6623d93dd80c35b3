#include "core/parallel.h"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <deque>
#include <exception>
#include <memory>
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

namespace {

// One parallel_for call. Chunks are claimed from `next`; whoever claims chunk c runs its items,
// so which thread runs an item never changes what it writes (the result is the same at any
// thread count). The caller always works on its own job, so a job finishes even when every pool
// thread is busy elsewhere (a parallel_for inside a parallel_for, files converted side by side).
struct Job {
  size_t count = 0, grain = 1, chunks = 0;
  const std::function<void(size_t)>* fn = nullptr;  // valid while a chunk below `chunks` runs
  std::atomic<size_t> next{0};
  std::atomic<int> inflight{0};  // threads inside run(): the caller waits for 0 once work is out
  int helpers_wanted = 0;        // pool threads still to join (under Pool::mutex)
  std::mutex mutex;
  std::condition_variable idle;
  std::exception_ptr first_error;

  // Claims and runs chunks until none is left. `inflight` is raised before a claim, so once the
  // caller has seen next >= chunks and inflight == 0, no thread can still call fn: a late
  // thread's claim is past the end and it leaves without touching fn.
  void run() {
    inflight.fetch_add(1);
    for (;;) {
      const size_t c = next.fetch_add(1);
      if (c >= chunks) break;
      const size_t end = std::min(count, (c + 1) * grain);
      try {
        for (size_t i = c * grain; i < end; ++i) (*fn)(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!first_error) first_error = std::current_exception();
        next = chunks;  // stop handing out work
        break;
      }
    }
    if (inflight.fetch_sub(1) == 1) {
      std::lock_guard<std::mutex> lock(mutex);
      idle.notify_all();
    }
  }
};

// Threads started once and kept for the process (a conversion makes 35–63 parallel_for calls;
// starting threads at each cost ≈ 5 ms CPU and far more wall time on a loaded machine,
// docs/performance-real.md "What is left, and why"). Never destroyed: threads blocked in wait()
// end with the process, and no static destructor can run while a job is out.
class Pool {
 public:
  static Pool& get() {
    static Pool* pool = new Pool;
    return *pool;
  }

  // Offers `job` to up to `helpers` pool threads, starting threads up to that many.
  void offer(const std::shared_ptr<Job>& job, int helpers) {
    std::lock_guard<std::mutex> lock(mutex_);
    job->helpers_wanted = helpers;
    queue_.push_back(job);
    while (int(threads_.size()) < helpers) threads_.emplace_back([this] { serve(); });
    wake_.notify_all();
  }

  // Takes `job` off the queue if no pool thread took it yet (the caller finished it alone).
  void withdraw(const std::shared_ptr<Job>& job) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = std::find(queue_.begin(), queue_.end(), job);
    if (it != queue_.end()) queue_.erase(it);
  }

 private:
  void serve() {
    for (;;) {
      std::shared_ptr<Job> job;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [this] { return !queue_.empty(); });
        job = queue_.front();
        if (--job->helpers_wanted <= 0) queue_.pop_front();
      }
      job->run();
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::shared_ptr<Job>> queue_;
  std::vector<std::thread> threads_;
};

}  // namespace

void parallel_for(size_t count, int threads, size_t grain, const std::function<void(size_t)>& fn) {
  if (count == 0) return;
  grain = std::max<size_t>(grain, 1);
  const size_t chunks = (count + grain - 1) / grain;
  const int n = int(std::min<size_t>(size_t(resolve_threads(threads)), chunks));
  if (n <= 1) {
    for (size_t i = 0; i < count; ++i) fn(i);
    return;
  }
  auto job = std::make_shared<Job>();
  job->count = count;
  job->grain = grain;
  job->chunks = chunks;
  job->fn = &fn;
  Pool& pool = Pool::get();
  pool.offer(job, n - 1);
  job->run();
  pool.withdraw(job);
  {
    std::unique_lock<std::mutex> lock(job->mutex);
    job->idle.wait(lock, [&] { return job->inflight.load() == 0; });
  }
  if (job->first_error) std::rethrow_exception(job->first_error);
}

}  // namespace ahd
