// Progress on a terminal and Ctrl-C: what a person at a terminal sees while a conversion runs.
#pragma once
#include <ahd/convert.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <string>

namespace ahd::cli {

// The flag SIGINT or SIGTERM raises (installed by install_interrupt_handler): conversions pass it
// as their cancel flag, stop at their next step, and nothing is published.
const std::atomic<bool>* interrupt_flag();
void install_interrupt_handler();

// Sets options->progress to a printer of one line per stage on stderr, updated in place
// ("fit  42 %  1.2 s  ETA 1.6 s"), when stderr is a terminal and `quiet` is false; otherwise
// leaves it unset (nothing extra in pipes and logs). Sets options->cancel to interrupt_flag().
void attach_terminal_progress(ConversionOptions* options, bool quiet);

// A batch's one line on stderr, redrawn in place: "files 3/8 done  4.2 s", and while a file is
// converted alone, its stage ("  big.exr: fit 42 %"). Only when stderr is a terminal and `quiet`
// is false. Every method may be called from any thread; error lines go through error() so that
// they never land in the middle of the line.
class BatchProgress {
 public:
  BatchProgress(size_t files, bool quiet);
  void file_done();
  // The progress callback of a file converted alone (empty when there is no line to draw).
  std::function<void(const char* stage, double fraction)> stage_of(const std::string& file);
  // Prints "ahdpack: error: <what>" on its own line, on stderr (terminal or not).
  void error(const std::string& what);
  // Clears the line (before the summary table).
  void finish();

 private:
  void draw(bool force);  // with lock_ held
  std::mutex lock_;
  bool on_ = false;
  size_t files_ = 0, done_ = 0;
  std::string stage_;  // "big.exr: fit 42 %" while a file runs alone
  std::chrono::steady_clock::time_point start_;
  double last_draw_ = -1;
};

}  // namespace ahd::cli
