// The batch's schedule: small files side by side, large and unknown ones alone, in input order.
// The batch through the command: tests/integration/cli_batch_test.cpp.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>

#include "cli/batch_schedule.h"
#include "cli_runner.h"
#include "image/sh_exr.h"
#include "sample/analytic_baker.h"
#include "cli_batch_fixture.h"

namespace fs = std::filesystem;
using ahd_test::run_cli;

using namespace ahd_fixture::cli_batch_fixture;

TEST(BatchSchedule, SmallFilesSideBySideLargeAndUnknownAloneInInputOrder) {
  using ahd::cli::kSmallBatchTexels;
  // Inputs: small, large, unreadable header (0), small at the limit, just past it, small.
  const std::vector<size_t> texels = {256 * 256, 1024 * 1024, 0, kSmallBatchTexels, kSmallBatchTexels + 1, 16 * 16};
  const ahd::cli::BatchPlan p = ahd::cli::plan_batch(texels, 2);
  EXPECT_EQ(p.small, (std::vector<size_t>{0, 3, 5}));
  EXPECT_EQ(p.large, (std::vector<size_t>{1, 2, 4}));
  EXPECT_EQ(p.jobs, 2);
  EXPECT_EQ(p.threads, 2);
  // No more jobs than small files, nor than threads.
  EXPECT_EQ(ahd::cli::plan_batch({100, 100, 100}, 8).jobs, 3);
  EXPECT_EQ(ahd::cli::plan_batch({100, 100, 100, 100, 100}, 4).jobs, 4);
  // One thread, or one small file: everything alone, in input order.
  for (const auto& [t, n] : std::vector<std::pair<std::vector<size_t>, int>>{{texels, 1}, {{100, 0, 1u << 24}, 2}}) {
    const ahd::cli::BatchPlan q = ahd::cli::plan_batch(t, n);
    EXPECT_TRUE(q.small.empty());
    EXPECT_EQ(q.jobs, 1);
    ASSERT_EQ(q.large.size(), t.size());
    for (size_t i = 0; i < t.size(); ++i) EXPECT_EQ(q.large[i], i);
  }
}
