// What the batch tests share (tests/unit batch_schedule_test.cpp, tests/integration cli_batch_test.cpp).
#pragma once
#include <gtest/gtest.h>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include "cli/batch_schedule.h"
#include "cli_runner.h"
#include "image/sh_exr.h"
#include "sample/analytic_baker.h"

namespace ahd_fixture::cli_batch_fixture {

using namespace ::ahd;

namespace fs = std::filesystem;
using ahd_test::run_cli;

inline std::string file_bytes(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

// Every file of a folder but the reports (their seconds differ from run to run), name → bytes.
inline std::map<std::string, std::string> outputs_in(const fs::path& d) {
  std::map<std::string, std::string> m;
  for (const auto& e : fs::directory_iterator(d)) {
    const std::string name = e.path().filename().string();
    if (name.size() > 12 && name.compare(name.size() - 12, 12, ".report.json") == 0) continue;
    m[name] = file_bytes(e.path());
  }
  return m;
}


}  // namespace ahd_fixture::cli_batch_fixture
