// The lab's subcommands (bench, report): measurements for the project's own work, kept apart from
// the product's commands under one help heading. Only this folder links ahd_lab.
#include <CLI/CLI.hpp>

#include "cli/commands.h"

namespace ahd::cli {

void add_lab_commands(CLI::App& app) {
  add_bench_command(app);
  add_report_command(app);
  for (const char* name : {"bench", "report"})
    app.get_subcommand(name)->group("Lab (measurements; not needed to convert)");
}

}  // namespace ahd::cli
