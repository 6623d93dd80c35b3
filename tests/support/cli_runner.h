// Runs the built ahdpack binary from tests and captures what it prints.
#pragma once
#include <string>
#include <vector>

namespace ahd_test {

struct CliResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

// Runs AHD_CLI_PATH with the arguments (each shell-quoted).
CliResult run_cli(const std::vector<std::string>& args);

// Runs a shell command line; returns what it writes to stdout (redirect 2>&1 for stderr too).
std::string run_shell(const std::string& command);

// The path of plane `plane` of the conversion whose manifest is `manifest` (plane files are
// content-addressed, NAME.<plane>.<hash>.<ext>; the manifest names them). "" when absent.
std::string plane_file(const std::string& manifest, const std::string& plane);

// A fresh empty folder under the system temp dir.
std::string temp_dir(const std::string& tag);

}  // namespace ahd_test
