// What the atlas tests share (tests/unit and tests/integration baker_atlas_test.cpp).
#pragma once
#include <gtest/gtest.h>
#include <cstring>
#include <fstream>
#include "files/file_io.h"
#include "files/container_file.h"
#include "bakers/godot/godot_import.h"
#include "bakers/layout_detect.h"
#include "bakers/layout_pages.h"
#include "layout_test_scene.h"
#include "pipeline/manifest.h"
#include "test_data.h"

namespace ahd_fixture::baker_atlas_fixture {

namespace fs = std::filesystem;
using namespace ::ahd;
using namespace layout_test;

const fs::path kVermilion = ahd_test::test_data("bakes/godot42-vermilion");

inline bool contains(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

// Page p of a Godot-style atlas: the world scene with page-dependent lighting (L0 scaled, L1 axes
// permuted and signed), so that every page converts to different planes.
inline void page_linear(const WorldScene& w, size_t i, int c, int page, double* l0, double l1[3]) {
  double a, b[3];
  world_linear(w, i, c, &a, b);
  *l0 = a * (1 + 0.5 * page);
  const int s = page % 3;
  const double sign = page & 1 ? -1 : 1;
  for (int k = 0; k < 3; ++k) l1[k] = sign * b[(k + s) % 3] * (1 + 0.5 * page);
}

// Godot ≥ 4.4 packed atlas: `pages` pages stacked page-major (each: L0, L1y, L1z, L1x), half.
inline void write_godot_atlas(const WorldScene& w, const std::string& path, int first_page, int pages) {
  ImageF img(N, 4 * N * pages, 3);
  for (int p = 0; p < pages; ++p)
    for (size_t i = 0; i < w.tangent.texels(); ++i) {
      const int x = int(i % N), y = int(i / N) + 4 * N * p;
      for (int c = 0; c < 3; ++c) {
        double l0, l1[3];
        page_linear(w, i, c, first_page + p, &l0, l1);
        img.at(x, y)[c] = float(l0);
        const double yzx[3] = {l1[1], l1[2], l1[0]};
        for (int k = 0; k < 3; ++k)
          img.at(x, y + (k + 1) * N)[c] = l0 > 0 ? float(std::clamp(yzx[k] / (8 * l0) + 0.5, 0.0, 1.0)) : 0.5f;
      }
    }
  write_image(path, img, /*half=*/true, {"R", "G", "B"});
}

inline void write_import(const std::string& exr, int slices) {
  std::ofstream f(exr + ".import");
  f << "[remap]\n\nimporter=\"2d_array_texture\"\ntype=\"CompressedTexture2DArray\"\n\n[params]\n\n"
       "slices/horizontal=1\nslices/vertical="
    << slices << "\n";
}

inline void write_project(const fs::path& dir, const std::string& version) {
  std::ofstream f(dir / "project.godot");
  f << "config_version=5\n\n[application]\n\nconfig/features=PackedStringArray(\"" << version << "\", \"Forward Plus\")\n";
}

inline Manifest read_manifest(const fs::path& p) {
  const std::vector<uint8_t> b = read_file_bytes(p.string());
  return manifest_from_json(std::string(b.begin(), b.end()), p.string());
}

}  // namespace ahd_fixture::baker_atlas_fixture
