// Progress on a terminal and Ctrl-C: what a person at a terminal sees while a conversion runs.
#pragma once
#include <ahd/convert.h>

#include <atomic>

namespace ahd::cli {

// The flag SIGINT raises (installed by install_interrupt_handler): conversions pass it as their
// cancel flag, stop at their next step, and nothing is published.
const std::atomic<bool>* interrupt_flag();
void install_interrupt_handler();

// Sets options->progress to a printer of one line per stage on stderr, updated in place
// ("fit  42 %  1.2 s  ETA 1.6 s"), when stderr is a terminal and `quiet` is false; otherwise
// leaves it unset (nothing extra in pipes and logs). Sets options->cancel to interrupt_flag().
void attach_terminal_progress(ConversionOptions* options, bool quiet);

}  // namespace ahd::cli
