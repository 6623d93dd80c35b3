// Normals and coverage rasterised from a mesh in lightmap-UV space (mesh/lightmap_raster,
// io/mesh_io, convert --mesh): analytic normals on a tessellated cylinder, conservative coverage
// against an independent supersampled + exact-edge reference, the largest-area rule, glTF and OBJ
// giving the same texels (the v-flip rule), bad inputs, and --mesh equal to --normals end to end.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "cli_runner.h"
#include "files/container_file.h"
#include "core/error.h"
#include "bakers/baker_layout.h"
#include "image/image_io.h"
#include "scene/mesh_io.h"
#include "layout_test_scene.h"
#include "scene/lightmap_raster.h"
#include "sample/analytic_baker.h"
#include "sh/sh.h"
#include "mesh_raster_fixture.h"

namespace fs = std::filesystem;
using namespace ahd;
using namespace ahd_fixture::mesh_raster_fixture;

TEST(MeshRaster, CylinderNormalsMatchTheAnalyticNormalAtTheCentroid) {
  const fs::path d = ahd_test::temp_dir("mesh_cyl");
  const TestMesh cyl = cylinder();
  write_obj((d / "c.obj").string(), cyl);
  constexpr int W = 32;
  const MeshTriangles m = read_mesh_lightmap((d / "c.obj").string(), -1);
  ASSERT_EQ(m.indices.size(), size_t(kNt * kNz * 6));
  const RasterisedNormals r = rasterise_lightmap_normals(m, W, W);
  // The centroid of the winner's part of each texel, from 64×64 samples of the triangle (to 1/128
  // texel); the analytic normal there is (cos θ, sin θ, 0) with θ linear in the lightmap x.
  double worst = 0, sum = 0;
  int checked = 0, slivers = 0;
  for (int y = 0; y < W; ++y)
    for (int x = 0; x < W; ++x) {
      const size_t i = size_t(y) * W + x;
      if (!r.coverage[i]) continue;
      const auto tri = pixel_triangle(m, size_t(r.triangle[i]), W, W);
      double cx = 0, cy = 0;
      int n = 0;
      for (int sy = 0; sy < 64; ++sy)
        for (int sx = 0; sx < 64; ++sx) {
          const double px = x + (sx + 0.5) / 64, py = y + (sy + 0.5) / 64;
          if (strictly_inside(tri, px, py)) cx += px, cy += py, ++n;
        }
      if (n < 64) {  // under 1/64 of the texel: the sampled centroid is too coarse to judge
        ++slivers;
        continue;
      }
      cx /= n;
      const double th = (cx / W - 1.0 / 16) / 0.875 * (kPiD / 2);
      const double ref[3] = {std::cos(th), std::sin(th), 0};
      const double e = angle_to(&r.normals[i * 3], ref);
      worst = std::max(worst, e), sum += e, ++checked;
    }
  std::printf("cylinder %dx%d quads, %dx%d lightmap: %d texels checked (%d slivers skipped), normal error max %.2e rad, "
              "mean %.2e\n", kNt, kNz, W, W, checked, slivers, worst, sum / checked);
  // Chart: x ∈ [2, 30], y ∈ [2, 30] → 28×28 texels covered.
  EXPECT_EQ(checked + slivers, 28 * 28);
  EXPECT_GT(checked, 28 * 28 * 9 / 10);
  // Error sources: the normalised lerp of the vertex normals vs the true arc across one
  // Δθ = π/32 segment (at most 1.52e-5 rad), and the sampled centroid (θ runs 0.056 rad per
  // texel; exact for a texel wholly inside one triangle). Measured 1.7e-5.
  EXPECT_LT(worst, 1e-4);
  fs::remove_all(d);
}

TEST(MeshRaster, ConservativeCoverageEqualsTheSupersampledReference) {
  constexpr int W = 12, H = 10;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-3, 15);
  size_t covered = 0, texels_touched = 0;
  for (int t = 0; t < 300; ++t) {
    std::array<P2, 3> p;
    for (auto& q : p) q = {coord(rng), coord(rng)};
    if (t % 10 == 0) p[0] = {p[0].x * 1e6, p[0].y * 1e5};  // far outside: clipped to the image
    if (t % 25 == 1) p[2] = {p[1].x + 0.01, p[1].y + 0.003};  // a sliver
    const MeshTriangles m = single(p, W, H);
    const RasterisedNormals r = rasterise_lightmap_normals(m, W, H);
    const size_t c = check_coverage(m, W, H, r, "random triangle " + std::to_string(t));
    covered += c;
    for (size_t i = 0; i < r.coverage.size(); ++i)
      if (r.coverage[i]) {
        EXPECT_FLOAT_EQ(r.normals[i * 3 + 2], 1.0f);
      }
    if (::testing::Test::HasFailure()) break;
    texels_touched += c > 0;
  }
  // Meshes: the cylinder (shared edges, diagonals through texels) and its chart at another scale.
  const MeshTriangles cyl = to_triangles(cylinder());
  size_t mesh_cov = 0;
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{{32, 32}, {13, 7}, {64, 40}})
    mesh_cov += check_coverage(cyl, w, h, rasterise_lightmap_normals(cyl, w, h), "cylinder " + std::to_string(w));
  std::printf("random triangles: 300 (%zu touching the image), %zu texels covered = reference; cylinder meshes: %zu\n",
              texels_touched, covered, mesh_cov);
  EXPECT_GT(texels_touched, 200u);
}

TEST(MeshRaster, LargestAreaWinsTiesGoToTheLowestIndex) {
  constexpr int W = 4, H = 4;
  // A covers x ∈ [0, 1.3] of the image, B x ∈ [1.3, 4]; texel column 1: A 0.3, B 0.7.
  const std::array<P2, 3> A = {P2{1.3, -100}, P2{1.3, 100}, P2{-100, 0}}, B = {P2{1.3, -100}, P2{1.3, 100}, P2{100, 0}};
  for (bool a_first : {true, false}) {
    MeshTriangles m;
    // A's normal is +x, B's +y, in either order.
    for (const auto& [tri, n] : {std::pair{a_first ? A : B, a_first ? 1.0f : 0.0f}, std::pair{a_first ? B : A, a_first ? 0.0f : 1.0f}}) {
      const MeshTriangles s = single(tri, W, H, {n, 1 - n, 0});
      const uint32_t base = uint32_t(m.positions.size() / 3);
      m.positions.insert(m.positions.end(), s.positions.begin(), s.positions.end());
      m.normals.insert(m.normals.end(), s.normals.begin(), s.normals.end());
      m.uv.insert(m.uv.end(), s.uv.begin(), s.uv.end());
      for (uint32_t i : s.indices) m.indices.push_back(base + i);
    }
    const RasterisedNormals r = rasterise_lightmap_normals(m, W, H);
    const int32_t ia = a_first ? 0 : 1, ib = 1 - ia;
    for (int y = 0; y < H; ++y) {
      EXPECT_EQ(r.triangle[size_t(y) * W + 0], ia);
      EXPECT_EQ(r.triangle[size_t(y) * W + 1], ib) << "column 1: B has 0.7 of the texel, A 0.3";
      EXPECT_FLOAT_EQ(r.normals[(size_t(y) * W + 1) * 3 + 1], 1.0f);
      EXPECT_EQ(r.triangle[size_t(y) * W + 3], ib);
    }
  }
  // Two identical triangles: a tie in every texel, the lower index keeps it.
  const std::array<P2, 3> T = {P2{0.2, 0.3}, P2{3.7, 0.9}, P2{1.1, 3.8}};
  for (float first : {0.0f, 1.0f}) {
    MeshTriangles m = single(T, W, H, {first, 1 - first, 0});
    const MeshTriangles s = single(T, W, H, {1 - first, first, 0});
    m.positions.insert(m.positions.end(), s.positions.begin(), s.positions.end());
    m.normals.insert(m.normals.end(), s.normals.begin(), s.normals.end());
    m.uv.insert(m.uv.end(), s.uv.begin(), s.uv.end());
    m.indices.insert(m.indices.end(), {3, 4, 5});
    const RasterisedNormals r = rasterise_lightmap_normals(m, W, H);
    size_t n = 0;
    for (size_t i = 0; i < r.coverage.size(); ++i)
      if (r.coverage[i]) {
        ++n;
        EXPECT_EQ(r.triangle[i], 0);
        EXPECT_FLOAT_EQ(r.normals[i * 3], first);
      }
    EXPECT_GT(n, 8u);
  }
}

TEST(MeshRaster, DegenerateAndHostileValuesAreSkippedOrRefused) {
  constexpr int W = 8, H = 8;
  const float nan = std::nanf("");
  MeshTriangles m;
  // 0: covers the whole image from 1e30 away, no vertex normals → the face normal (winding).
  // 1: zero UV area. 2: NaN UV. 3: zero vertex normal → face normal. Triangles 1–3 come later
  // and are inside triangle 0's texels with smaller areas, so only 0 must win everywhere.
  m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0,  0, 0, 0, 1, 0, 0, 2, 0, 0,  0, 0, 0, 1, 0, 0, 0, 0, 1,  0, 0, 0, 0, 1, 0, 0, 0, 1};
  m.uv = {-1e30f, -1e30f, 3e30f, -1e30f, -1e30f, 3e30f,  0.1f, 0.1f, 0.2f, 0.2f, 0.3f, 0.3f,
          0.1f, 0.1f, nan, 0.5f, 0.1f, 0.6f,  0.1f, 0.1f, 0.6f, 0.1f, 0.1f, 0.6f};
  m.indices = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11};
  RasterisedNormals r = rasterise_lightmap_normals(m, W, H);
  for (size_t i = 0; i < r.coverage.size(); ++i) {
    ASSERT_EQ(r.coverage[i], 1);
    EXPECT_EQ(r.triangle[i], 0);
    EXPECT_FLOAT_EQ(r.normals[i * 3 + 2], 1.0f);  // cross(+x, +y)
  }
  // Alone, triangle 3 (vertex normals +y but one zero) takes its face normal cross(+y, +z) = +x.
  m.normals.assign(m.positions.size(), 0.0f);
  for (size_t v = 0; v < 12; ++v) m.normals[v * 3 + 1] = 1;  // +y everywhere …
  m.normals[9 * 3 + 1] = 0;                                   // … but vertex 9
  m.indices = {9, 10, 11};
  r = rasterise_lightmap_normals(m, W, H);
  size_t n = 0;
  for (size_t i = 0; i < r.coverage.size(); ++i)
    if (r.coverage[i]) {
      ++n;
      EXPECT_FLOAT_EQ(r.normals[i * 3 + 0], 1.0f);
    }
  EXPECT_GT(n, 4u);
  m.indices = {3, 4, 5, 6, 7, 8};  // nothing usable: nothing covered
  r = rasterise_lightmap_normals(m, W, H);
  EXPECT_EQ(std::count(r.coverage.begin(), r.coverage.end(), 1), 0);
  // Inconsistent buffers are refused, not read out of bounds.
  m.indices = {0, 1, 12};
  EXPECT_THROW(rasterise_lightmap_normals(m, W, H), Error);
  m.indices = {0, 1};
  EXPECT_THROW(rasterise_lightmap_normals(m, W, H), Error);
  m.indices = {0, 1, 2};
  m.uv.pop_back();
  EXPECT_THROW(rasterise_lightmap_normals(m, W, H), Error);
  EXPECT_THROW(rasterise_lightmap_normals(MeshTriangles{}, 0, 4), Error);
}

TEST(MeshRaster, GltfAndObjGiveTheSameTexelsRowZeroIsGltfVZero) {
  const fs::path d = ahd_test::temp_dir("mesh_formats");
  // The cylinder as OBJ (one UV set: the lightmap's, normals as they are) and as glTF (decoy
  // TEXCOORD_0, lightmap TEXCOORD_1, node rotated 90° about x): the default UV set of the glTF is
  // the second, the node transform is applied to positions and normals.
  const TestMesh cyl = cylinder();
  write_obj((d / "c.obj").string(), cyl);
  const double s = std::sqrt(0.5);
  write_gltf((d / "c.gltf").string(), cyl, {s, 0, 0, s});
  MeshReadInfo gi, oi;
  const MeshTriangles g = read_mesh_lightmap((d / "c.gltf").string(), -1, &gi);
  const MeshTriangles o = read_mesh_lightmap((d / "c.obj").string(), -1, &oi);
  EXPECT_EQ(gi.uv_set, 1);
  EXPECT_EQ(gi.uv_sets, 2);
  EXPECT_EQ(oi.uv_set, 0);
  EXPECT_EQ(gi.triangles, oi.triangles);
  for (int w : {32, 19}) {
    const RasterisedNormals rg = rasterise_lightmap_normals(g, w, w), ro = rasterise_lightmap_normals(o, w, w);
    EXPECT_EQ(rg.coverage, ro.coverage) << w;
    EXPECT_EQ(std::count(rg.coverage.begin(), rg.coverage.end(), 1), std::count(ro.coverage.begin(), ro.coverage.end(), 1));
    EXPECT_EQ(rg.triangle, ro.triangle) << w;
    double worst = 0;
    for (size_t i = 0; i < ro.coverage.size(); ++i) {
      if (!ro.coverage[i]) continue;
      // Rotation by 90° about x: (x, y, z) → (x, −z, y).
      const float* n = &ro.normals[i * 3];
      const double rot[3] = {n[0], -n[2], n[1]};
      worst = std::max(worst, angle_to(&rg.normals[i * 3], rot));
    }
    std::printf("glTF (rotated node, TEXCOORD_1) vs OBJ at %dx%d: same %zu texels and winners, normals within %.1e rad\n",
                w, w, size_t(std::count(ro.coverage.begin(), ro.coverage.end(), 1)), worst);
    EXPECT_LT(worst, 1e-6) << w;  // float rounding of the node rotation
  }
  // The absolute rule, not just agreement: glTF v = 0 (and OBJ v = 1) is lightmap row 0.
  TestMesh corner;
  corner.pos = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  corner.nrm = {0, 0, 1, 0, 0, 1, 0, 0, 1};
  corner.lm_uv = {0, 0, 0.5f, 0, 0, 0.5f};  // top-left quarter of the image, glTF convention
  corner.idx = {0, 1, 2};
  write_gltf((d / "t.gltf").string(), corner);
  write_obj((d / "t.obj").string(), corner);
  for (const char* f : {"t.gltf", "t.obj"}) {
    const RasterisedNormals r = rasterise_lightmap_normals(read_mesh_lightmap((d / f).string(), -1), 4, 4);
    EXPECT_EQ(r.coverage[0], 1) << f << ": texel (0, 0)";
    EXPECT_EQ(r.coverage[1], 1) << f;
    EXPECT_EQ(r.coverage[4], 1) << f;
    EXPECT_EQ(r.coverage[5], 0) << f << ": on the hypotenuse only";
    EXPECT_EQ(r.coverage[15], 0) << f;
    EXPECT_EQ(r.coverage[12], 0) << f << ": bottom-left";
  }
  fs::remove_all(d);
}
