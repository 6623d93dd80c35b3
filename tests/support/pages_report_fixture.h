// What the pages-report tests share (tests/unit and tests/integration pages_report_test.cpp).
#pragma once
#include <gtest/gtest.h>
#include <ahd/sample.h>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include "cli_runner.h"
#include "core/image.h"
#include "files/file_io.h"
#include "files/profile_file.h"
#include "image/image_io.h"
#include "pipeline/pages.h"
#include "pipeline/report_json.h"

namespace ahd_fixture::pages_report_fixture {

namespace fs = std::filesystem;
using namespace ::ahd;

inline bool contains(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

// Four different pages of one size: analytic scenes of seeds 1-4 with `k` rows of page k
// uncovered (so that every page has its own counts); page 3's L1 zeroed (alone, it drops the
// direction planes: I_z alone is exact).
inline std::vector<ShImage> four_pages() {
  std::vector<ShImage> pages;
  for (int k = 0; k < 4; ++k) {
    ShImage sh = bake_sample(32, 1, uint32_t(k + 1), 1);
    for (size_t i = 0; i < size_t(32 * 4 * k); ++i) sh.coverage[i] = 0;
    if (k == 3)
      for (size_t i = 0; i < sh.texels(); ++i)
        for (int j = 3; j < sh.coeffs * 3; ++j) sh.texel(i)[j] = 0;
    pages.push_back(std::move(sh));
  }
  return pages;
}

}  // namespace ahd_fixture::pages_report_fixture
