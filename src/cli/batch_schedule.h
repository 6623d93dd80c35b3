// How `convert IN1 IN2 … -o OUTDIR/` shares the machine between files: small files side by side,
// one thread each; large files one at a time with every thread. Bytes never depend on it (every
// conversion's bytes are independent of its thread count), only wall time and peak memory do.
#pragma once
#include <cstddef>
#include <functional>
#include <vector>

namespace ahd::cli {

// Largest input (texels of its file's header) converted beside others. Why: two threads speed one
// conversion up only 1.26× at 256², 1.32× at 512², 1.44× at 1024² (pc-bc, L2 sample, this
// 2-core machine), while files side by side keep both cores busy. But memory grows with texels: a 512² L2 conversion peaks ≈ 75 MB above the idle process
// (≈ 290 bytes a texel), a 1024² one ≈ 260 MB (docs/performance.md "Whole conversions"): with larger files
// one at a time, a batch needs at most its largest file's peak plus ≈ 75 MB per extra job (issue
// 12: peak memory matters).
constexpr int kSmallBatchSide = 512;
constexpr size_t kSmallBatchTexels = size_t(kSmallBatchSide) * kSmallBatchSide;

// The order of a batch. Every input is in exactly one list, each list in input order.
struct BatchPlan {
  std::vector<size_t> small;  // converted first, `jobs` at a time, each with 1 thread
  std::vector<size_t> large;  // then one at a time, each with `threads` threads
  int jobs = 1;
  int threads = 1;
};

// texels[i]: input i's texel count from its header, 0 when the header could not be read (run alone:
// an unknown size may be a large one). `threads` ≥ 1: the threads the batch may use. With one thread,
// or one small input, every input runs alone.
inline BatchPlan plan_batch(const std::vector<size_t>& texels, int threads) {
  BatchPlan p;
  p.threads = threads < 1 ? 1 : threads;
  for (size_t i = 0; i < texels.size(); ++i)
    (texels[i] > 0 && texels[i] <= kSmallBatchTexels ? p.small : p.large).push_back(i);
  p.jobs = int(p.small.size() < size_t(p.threads) ? p.small.size() : size_t(p.threads));
  if (p.jobs < 2) {  // nothing to run side by side: all alone, in input order
    p.small.clear();
    p.large.resize(texels.size());
    for (size_t i = 0; i < texels.size(); ++i) p.large[i] = i;
    p.jobs = 1;
  }
  return p;
}

// Runs convert(i, threads) for every input of `plan`: plan.small on plan.jobs threads at once (1
// thread each), then plan.large one by one on this thread (plan.threads each). `convert` must catch
// its own errors except `stop`-worthy ones: when it throws, no further input starts, the running
// ones finish, and the first exception is rethrown here (Ctrl-C's ahd::Cancelled).
void run_batch_plan(const BatchPlan& plan, const std::function<void(size_t index, int threads)>& convert);

}  // namespace ahd::cli
