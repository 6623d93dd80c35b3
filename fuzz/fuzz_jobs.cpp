// Batch job files (read_bake_jobs, `convert --jobs FILE`, issue 44): JSON naming each job's input
// and options. Seeds: tests/data/bevy/cornell.jobs.json and a small one from scripts/fuzz.sh.
#include "bakers/bake_jobs.h"
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = ahd_fuzz::write_temp(data, size, ".jobs.json");
  ahd_fuzz::expect_clean([&] {
    const std::vector<ahd::BakeJob> jobs = ahd::read_bake_jobs(path, ahd::BakeInput{});
    for (const ahd::BakeJob& j : jobs)
      if (j.input.input.empty()) __builtin_trap();  // "a job without input" is an error
  });
  return 0;
}
