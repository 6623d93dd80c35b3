// ahdpack bench convert on Windows: not available. The POSIX form (lab/cmd_bench_convert.cpp) measures
// each conversion's memory in a re-executed child (fork, execv, /proc, getrusage), not ported
// (CreateProcessW, GetProcessMemoryInfo would be its Windows form; docs/platforms.md "Windows").
#ifdef _WIN32
#include "cli/commands.h"
#include "core/error.h"

namespace ahd::cli {

void add_bench_convert_command(CLI::App& bench) {
  CLI::App* c = bench.add_subcommand("convert", "Whole conversions' time and memory (not on Windows)");
  c->allow_extras();
  c->callback([] { throw Error("bench convert: not available on Windows (it measures child processes through fork)"); });
}

}  // namespace ahd::cli
#endif  // _WIN32
