// The data the tests read: tests/data/ of the source tree (AHD_TEST_DATA_DIR, set by
// tests/CMakeLists.txt), carried by the repository with its licences (tests/data/README.md).
#pragma once
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace ahd_test {

// The source tree (AHD_SOURCE_DIR): the docs and scripts some tests read.
inline const std::filesystem::path kSourceDir = AHD_SOURCE_DIR;

// The Chromium binary the browser tests run, or "" when none is installed (they skip).
inline std::string chromium_binary() {
  for (const char* p : {"/usr/bin/chromium", "/usr/bin/chromium-browser"})
    if (std::filesystem::exists(p)) return p;
  return "";
}

inline std::filesystem::path test_data(const std::string& relative) {
  return std::filesystem::path(AHD_TEST_DATA_DIR) / relative;
}

}  // namespace ahd_test

// Skips the running test, naming the file, when a data file is missing (a trimmed checkout):
// missing data is a skip with a reason, never a failure.
#define AHD_REQUIRE_DATA(file)                                                                \
  do {                                                                                        \
    const std::filesystem::path ahd_required_file_(file);                                     \
    if (!std::filesystem::exists(ahd_required_file_))                                         \
      GTEST_SKIP() << ahd_required_file_.string() << " missing (tests/data/README.md)";       \
  } while (0)
