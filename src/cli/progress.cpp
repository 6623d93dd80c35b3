#include "cli/progress.h"

#include <chrono>
#include <csignal>
#include <cstdio>
#include <memory>
#include <string>

#include "files/os_files.h"

namespace ahd::cli {
namespace {

std::atomic<bool> g_interrupted{false};

void on_sigint(int) { g_interrupted.store(true); }

// One stage's line, redrawn with '\r' and finished with '\n' when the next stage starts.
struct TerminalProgress {
  using Clock = std::chrono::steady_clock;
  std::string stage;
  Clock::time_point start;
  double last_print = -1;

  void operator()(const char* name, double fraction) {
    const auto now = Clock::now();
    if (stage != name) {
      if (!stage.empty()) std::fputc('\n', stderr);
      stage = name;
      start = now;
      last_print = -1;
    }
    const double elapsed = std::chrono::duration<double>(now - start).count();
    if (fraction < 1 && elapsed - last_print < 0.1 && last_print >= 0) return;  // at most 10 redraws/s
    last_print = elapsed;
    char eta[32] = "";
    if (fraction > 0.02 && fraction < 1) std::snprintf(eta, sizeof eta, "  ETA %.1f s", elapsed * (1 - fraction) / fraction);
    std::fprintf(stderr, "\r\033[K%-8s %3.0f %%  %.1f s%s", stage.c_str(), fraction * 100, elapsed, eta);
    if (stage == "write" && fraction >= 1) std::fputc('\n', stderr), stage.clear();
    std::fflush(stderr);
  }
};

}  // namespace

const std::atomic<bool>* interrupt_flag() { return &g_interrupted; }

void install_interrupt_handler() {
  std::signal(SIGINT, on_sigint);
  std::signal(SIGTERM, on_sigint);
}

void attach_terminal_progress(ConversionOptions* options, bool quiet) {
  install_interrupt_handler();
  options->cancel = interrupt_flag();
  if (quiet || !os::stderr_is_terminal()) return;
  auto p = std::make_shared<TerminalProgress>();
  options->progress = [p](const char* stage, double fraction) { (*p)(stage, fraction); };
}

BatchProgress::BatchProgress(size_t files, bool quiet)
    : on_(!quiet && os::stderr_is_terminal()), files_(files), start_(std::chrono::steady_clock::now()) {
  std::lock_guard<std::mutex> l(lock_);
  draw(true);
}

void BatchProgress::draw(bool force) {
  if (!on_) return;
  const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (!force && t - last_draw_ < 0.1) return;  // at most 10 redraws/s
  last_draw_ = t;
  std::fprintf(stderr, "\r\033[Kfiles %zu/%zu done  %.1f s%s%s", done_, files_, t, stage_.empty() ? "" : "  ",
               stage_.c_str());
  std::fflush(stderr);
}

void BatchProgress::file_done() {
  std::lock_guard<std::mutex> l(lock_);
  ++done_;
  stage_.clear();
  draw(true);
}

std::function<void(const char*, double)> BatchProgress::stage_of(const std::string& file) {
  if (!on_) return {};
  return [this, file](const char* stage, double fraction) {
    char pct[16];
    std::snprintf(pct, sizeof pct, " %.0f %%", fraction * 100);
    std::lock_guard<std::mutex> l(lock_);
    stage_ = file + ": " + stage + pct;
    draw(fraction >= 1);
  };
}

void BatchProgress::error(const std::string& what) {
  std::lock_guard<std::mutex> l(lock_);
  if (on_) std::fputs("\r\033[K", stderr);
  std::fprintf(stderr, "ahdpack: error: %s\n", what.c_str());
  draw(true);
}

void BatchProgress::finish() {
  std::lock_guard<std::mutex> l(lock_);
  if (on_) std::fputs("\r\033[K", stderr), std::fflush(stderr);
  on_ = false;
}

}  // namespace ahd::cli
