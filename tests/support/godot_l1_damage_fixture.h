// What the damaged-L1 tests share (tests/unit and tests/integration godot_l1_damage_test.cpp).
#pragma once
#include <gtest/gtest.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include "cli_runner.h"
#include "godot_turned_bake.h"
#include "test_data.h"
#include "bakers/baker_layout.h"
#include "bakers/godot/godot_scene.h"
#include "files/file_io.h"
#include "files/profile_file.h"
#include "image/image_io.h"
#include "pipeline/convert.h"
#include "scene/lightmap_raster.h"
#include "scene/placement.h"

namespace ahd_fixture::godot_l1_damage_fixture {

namespace fs = std::filesystem;
using namespace ::ahd;

const fs::path kScenes = ahd_test::test_data("bakes/godot42-vermilion") / "project" / "scenes";

inline bool contains(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

#define NEED_BAKE() \
  if (!fs::exists(kScenes / "world.tscn")) GTEST_SKIP() << "no " << kScenes / "world.tscn"

// The real bake read as convert reads it (the scene's normals), the normals turned about x by
// `degrees`.
inline ShImage real_bake(double degrees) { return ahd_test::read_turned_bake(kScenes, degrees).sh; }

// Negative L1 set to 0, as the denoiser left it.
inline void clamp_l1(ShImage* sh) {
  for (size_t i = 0; i < sh->texels(); ++i)
    for (int j = 3; j < 12; ++j) sh->texel(i)[j] = std::max(sh->texel(i)[j], 0.0f);
}

inline PipelineResult convert_one(const ShImage& sh) {
  PipelineOptions opt;
  opt.max_levels = 1;
  return run_conversion(sh, load_profile("uncompressed"), opt);
}

inline bool has_warning(const PipelineResult& r, const std::string& what) {
  for (const std::string& w : r.warnings)
    if (contains(w, what)) return true;
  return false;
}

inline void print_figures(const char* what, const PipelineResult& r) {
  std::printf("%s: L1 negative y %.3f z %.3f x %.3f, zero y %.3f z %.3f x %.3f; rules %.4f; %zu warning(s)\n", what,
              double(r.l1.negative[0]) / double(r.l1.values[0]), double(r.l1.negative[1]) / double(r.l1.values[1]),
              double(r.l1.negative[2]) / double(r.l1.values[2]), double(r.l1.zero[0]) / double(r.l1.values[0]),
              double(r.l1.zero[1]) / double(r.l1.values[1]), double(r.l1.zero[2]) / double(r.l1.values[2]),
              rules_share(r.fit_stats), r.warnings.size());
}

}  // namespace ahd_fixture::godot_l1_damage_fixture
