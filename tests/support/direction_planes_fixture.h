// What the direction-planes tests share (tests/unit and tests/integration direction_planes_test.cpp).
#pragma once
#include <gtest/gtest.h>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include "cli_runner.h"
#include "files/container_file.h"
#include "core/error.h"
#include "files/profile_file.h"
#include "image/image_io.h"
#include "pipeline/convert.h"
#include "pipeline/manifest.h"
#include "sample/analytic_baker.h"

namespace ahd_fixture::direction_planes_fixture {

namespace fs = std::filesystem;
using namespace ::ahd;
using ahd_test::run_cli;

inline nlohmann::json read_json(const fs::path& p) {
  std::ifstream f(p);
  return nlohmann::json::parse(f);
}

inline std::vector<std::string> plane_names(const nlohmann::json& manifest) {
  std::vector<std::string> names;
  for (const auto& p : manifest.at("planes")) names.push_back(p.at("name").get<std::string>());
  return names;
}

// A plain lightmap (E/π along the normal) as the `plain` layout reads it.
inline fs::path write_plain(const fs::path& dir) {
  ImageF img(8, 6, 3);
  for (size_t i = 0; i < img.data.size(); ++i) img.data[i] = 0.2f + 0.05f * float(i % 7);
  write_image((dir / "flat.exr").string(), img);
  return dir / "flat";
}

}  // namespace ahd_fixture::direction_planes_fixture
