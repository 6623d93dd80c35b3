// The ahdpack subcommands. Each file cmd_*.cpp adds one (or a pair of) subcommand(s) to the app;
// callbacks throw ahd::Error on bad input, which main() turns into one line on stderr and exit 1.
#pragma once
#include <CLI/CLI.hpp>

namespace ahd::cli {

void add_convert_command(CLI::App& app);     // cmd_convert.cpp
void add_layouts_command(CLI::App& app);     // cmd_convert.cpp: the baker layout presets
void add_decode_command(CLI::App& app);      // cmd_decode.cpp
void add_inspect_command(CLI::App& app);     // cmd_inspect.cpp
void add_compress_commands(CLI::App& app);   // cmd_compress.cpp: compress + decompress
void add_sample_command(CLI::App& app);      // cmd_sample.cpp
void add_transcode_command(CLI::App& app);   // cmd_transcode.cpp
void add_preview_command(CLI::App& app);     // cmd_preview.cpp: HTML page of a conversion
void add_verify_command(CLI::App& app);      // cmd_verify.cpp: a conversion within bounds (users' CI)
void add_scene_command(CLI::App& app);       // cmd_scene.cpp: the placed scene as glTF

// The lab (src/cli/lab/, linking ahd_lab): measurements of the codecs and the fit, not needed to
// convert. Listed under their own heading in `ahdpack --help`.
void add_lab_commands(CLI::App& app);        // lab/lab_commands.cpp: bench, report
void add_bench_command(CLI::App& app);       // lab/cmd_bench.cpp
void add_bench_convert_command(CLI::App& bench);  // lab/cmd_bench_convert.cpp: `bench convert` under `bench`
void add_report_command(CLI::App& app);      // lab/cmd_report.cpp: hard-cases, eps, profiles
void add_report_fit_command(CLI::App* report);  // lab/cmd_report_fit.cpp: `report fit`, linear vs refined d
void add_report_truth_command(CLI::App* report);  // lab/cmd_report_truth.cpp: `report truth`, against path-traced lighting

}  // namespace ahd::cli
