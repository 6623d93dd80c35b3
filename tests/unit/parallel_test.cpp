// parallel_for over the process's persistent thread pool (src/core/parallel.cpp): every item runs
// exactly once whatever the thread count and grain, errors reach the caller, and calls made from
// inside a call or from several threads at once all finish.
#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "core/parallel.h"

namespace {

TEST(Parallel, EveryItemRunsExactlyOnce) {
  for (int threads : {1, 2, 3, 8}) {
    for (size_t count : {size_t(1), size_t(7), size_t(64), size_t(1000)}) {
      for (size_t grain : {size_t(1), size_t(3), size_t(64), size_t(5000)}) {
        std::vector<std::atomic<int>> hits(count);
        ahd::parallel_for(count, threads, grain, [&](size_t i) { hits[i].fetch_add(1); });
        for (size_t i = 0; i < count; ++i)
          ASSERT_EQ(hits[i].load(), 1) << "item " << i << " of " << count << ", threads " << threads
                                       << ", grain " << grain;
      }
    }
  }
}

TEST(Parallel, AnItemsErrorReachesTheCallerAndStopsTheWork) {
  // Every item throws: a thread stops at its first error and no chunk is handed out after the
  // first one, so at most one item per thread runs (4: the caller and 3 pool threads), whatever
  // the scheduling (a test that throws at one item cannot say how many others ran before it).
  std::atomic<int> ran{0};
  EXPECT_THROW(ahd::parallel_for(100000, 4, 1,
                                 [&](size_t i) {
                                   ran.fetch_add(1);
                                   throw std::runtime_error("item " + std::to_string(i));
                                 }),
               std::runtime_error);
  EXPECT_GE(ran.load(), 1);
  EXPECT_LE(ran.load(), 4);
  // One item's error, the others fine: the error reaches the caller.
  EXPECT_THROW(ahd::parallel_for(1000, 4, 3,
                                 [&](size_t i) {
                                   if (i == 500) throw std::runtime_error("item 500");
                                 }),
               std::runtime_error);
  // The pool is still usable after errors.
  std::atomic<int> after{0};
  ahd::parallel_for(1000, 4, 7, [&](size_t) { after.fetch_add(1); });
  EXPECT_EQ(after.load(), 1000);
}

TEST(Parallel, CallsInsideCallsFinish) {
  std::vector<std::atomic<int>> hits(16 * 200);
  ahd::parallel_for(16, 4, 1, [&](size_t outer) {
    ahd::parallel_for(200, 4, 5, [&](size_t inner) { hits[outer * 200 + inner].fetch_add(1); });
  });
  for (auto& h : hits) ASSERT_EQ(h.load(), 1);
}

TEST(Parallel, CallsFromSeveralThreadsAtOnceFinish) {
  constexpr int kCallers = 6, kCalls = 40;
  std::vector<std::atomic<long>> sums(kCallers);
  std::vector<std::thread> callers;
  for (int c = 0; c < kCallers; ++c)
    callers.emplace_back([&, c] {
      for (int k = 0; k < kCalls; ++k)
        ahd::parallel_for(100, 3, 4, [&](size_t i) { sums[c].fetch_add(long(i)); });
    });
  for (auto& t : callers) t.join();
  for (int c = 0; c < kCallers; ++c) EXPECT_EQ(sums[c].load(), long(kCalls) * 4950) << "caller " << c;
}

TEST(Parallel, ResultsDoNotDependOnTheThreadCount) {
  std::vector<double> one(5000), many(5000);
  auto work = [](std::vector<double>& out) {
    return [&out](size_t i) {
      double x = double(i);
      for (int k = 0; k < 20; ++k) x = x * 0.5 + 1.0 / (1.0 + x);
      out[i] = x;
    };
  };
  ahd::parallel_for(one.size(), 1, 16, work(one));
  ahd::parallel_for(many.size(), 8, 16, work(many));
  EXPECT_EQ(one, many);
}

}  // namespace
