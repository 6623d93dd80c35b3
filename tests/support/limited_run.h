// The command line run in a child process under an address-space limit (RLIMIT_AS, what
// `ulimit -v` sets): the bad-input rounds' memory and time bounds.
#pragma once
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "file_bytes.h"

namespace ahd_test {

struct LimitedRun {
  int exit_code = -1;
  long peak_rss_kb = 0;
  double seconds = 0;
  std::string output;
};

// Runs the CLI in a child under RLIMIT_AS = `as_bytes` (what `ulimit -v` sets), stdout and stderr
// to `log`; the peak RSS is the child's own (wait4), the wall time is printed, never asserted.
inline LimitedRun run_cli_limited(const std::vector<std::string>& args, const std::filesystem::path& log, rlim_t as_bytes) {
  std::vector<std::string> argv_s = {AHD_CLI_PATH};
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid == 0) {
    const rlimit lim{as_bytes, as_bytes};
    setrlimit(RLIMIT_AS, &lim);
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 1);
    dup2(fd, 2);
    execv(argv[0], argv.data());
    _exit(127);
  }
  LimitedRun r;
  int status = 0;
  rusage ru{};
  wait4(pid, &status, 0, &ru);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.peak_rss_kb = ru.ru_maxrss;
  r.output = ahd_test::read_text(log);
  return r;
}

}  // namespace ahd_test
