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

namespace fs = std::filesystem;
using namespace ahd;

namespace {

constexpr double kPiD = 3.14159265358979323846;

// A test mesh; UVs in the image convention (v down = glTF's): writers convert for OBJ.
struct TestMesh {
  std::vector<float> pos, nrm, lm_uv, tex_uv;  // tex_uv: a decoy set 0 for glTF (empty = none)
  std::vector<uint32_t> idx;
  size_t verts() const { return pos.size() / 3; }
};

MeshTriangles to_triangles(const TestMesh& m) {
  MeshTriangles t{m.pos, m.nrm, m.lm_uv, m.idx};
  for (size_t i = 1; i < t.uv.size(); i += 2) t.uv[i] = 1.0f - t.uv[i];  // to the OBJ convention
  return t;
}

void write_obj(const std::string& path, const TestMesh& m, bool normals = true, bool uvs = true) {
  std::ofstream f(path);
  char b[160];
  for (size_t v = 0; v < m.verts(); ++v) {
    std::snprintf(b, sizeof b, "v %.9g %.9g %.9g\n", m.pos[v * 3], m.pos[v * 3 + 1], m.pos[v * 3 + 2]);
    f << b;
    if (uvs) {
      std::snprintf(b, sizeof b, "vt %.9g %.9g\n", m.lm_uv[v * 2], 1.0f - m.lm_uv[v * 2 + 1]);  // OBJ: v up
      f << b;
    }
    if (normals) {
      std::snprintf(b, sizeof b, "vn %.9g %.9g %.9g\n", m.nrm[v * 3], m.nrm[v * 3 + 1], m.nrm[v * 3 + 2]);
      f << b;
    }
  }
  for (size_t t = 0; t < m.idx.size(); t += 3) {
    f << "f";
    for (int k = 0; k < 3; ++k) {
      const uint32_t i = m.idx[t + size_t(k)] + 1;
      f << " " << i;
      if (uvs && normals) f << "/" << i << "/" << i;
      else if (uvs) f << "/" << i;
      else if (normals) f << "//" << i;
    }
    f << "\n";
  }
}

std::string mesh_base64(const std::vector<uint8_t>& d) {
  static const char* a = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string s;
  for (size_t i = 0; i < d.size(); i += 3) {
    const uint32_t v = uint32_t(d[i]) << 16 | (i + 1 < d.size() ? uint32_t(d[i + 1]) << 8 : 0) |
                       (i + 2 < d.size() ? uint32_t(d[i + 2]) : 0);
    s += a[v >> 18 & 63];
    s += a[v >> 12 & 63];
    s += i + 1 < d.size() ? a[v >> 6 & 63] : '=';
    s += i + 2 < d.size() ? a[v & 63] : '=';
  }
  return s;
}

// A .gltf with one embedded base64 buffer. TEXCOORD_0 = tex_uv (when given), the lightmap UVs
// next; `rotation` (quaternion x y z w) on the node, which the loader must apply.
void write_gltf(const std::string& path, const TestMesh& m, const std::array<double, 4>& rotation = {0, 0, 0, 1}) {
  std::vector<uint8_t> buf;
  struct View {
    size_t offset, length;
  };
  std::vector<View> views;
  auto add = [&](const void* p, size_t bytes) {
    while (buf.size() % 4) buf.push_back(0);
    views.push_back({buf.size(), bytes});
    buf.insert(buf.end(), static_cast<const uint8_t*>(p), static_cast<const uint8_t*>(p) + bytes);
  };
  const bool two = !m.tex_uv.empty();
  add(m.pos.data(), m.pos.size() * 4);
  add(m.nrm.data(), m.nrm.size() * 4);
  if (two) add(m.tex_uv.data(), m.tex_uv.size() * 4);
  add(m.lm_uv.data(), m.lm_uv.size() * 4);
  add(m.idx.data(), m.idx.size() * 4);
  float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
  for (size_t v = 0; v < m.verts(); ++v)
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], m.pos[v * 3 + size_t(a)]), hi[a] = std::max(hi[a], m.pos[v * 3 + size_t(a)]);
  std::ostringstream j;
  j.precision(9);
  j << R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0,"rotation":[)" << rotation[0]
    << "," << rotation[1] << "," << rotation[2] << "," << rotation[3] << "]}],";
  j << R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,"NORMAL":1,)";
  if (two) j << R"("TEXCOORD_0":2,"TEXCOORD_1":3},"indices":4}]}],)";
  else j << R"("TEXCOORD_0":2},"indices":3}]}],)";
  j << R"("buffers":[{"byteLength":)" << buf.size() << R"(,"uri":"data:application/octet-stream;base64,)" << mesh_base64(buf)
    << R"("}],"bufferViews":[)";
  for (size_t i = 0; i < views.size(); ++i)
    j << (i ? "," : "") << R"({"buffer":0,"byteOffset":)" << views[i].offset << R"(,"byteLength":)" << views[i].length << "}";
  j << R"(],"accessors":[)";
  j << R"({"bufferView":0,"componentType":5126,"count":)" << m.verts() << R"(,"type":"VEC3","min":[)" << lo[0] << ","
    << lo[1] << "," << lo[2] << R"(],"max":[)" << hi[0] << "," << hi[1] << "," << hi[2] << "]},";
  j << R"({"bufferView":1,"componentType":5126,"count":)" << m.verts() << R"(,"type":"VEC3"},)";
  size_t view = 2;
  if (two) j << R"({"bufferView":)" << view++ << R"(,"componentType":5126,"count":)" << m.verts() << R"(,"type":"VEC2"},)";
  j << R"({"bufferView":)" << view++ << R"(,"componentType":5126,"count":)" << m.verts() << R"(,"type":"VEC2"},)";
  j << R"({"bufferView":)" << view << R"(,"componentType":5125,"count":)" << m.idx.size() << R"(,"type":"SCALAR"}]})";
  std::ofstream(path) << j.str();
}

// A quarter cylinder (radius 1, axis z, θ ∈ [0, π/2], z ∈ [0, 1]), nt × nz quads, outward normals.
// Lightmap chart: x = 1/16 + 7/8·θ/(π/2), y = 1/16 + 7/8·z (image convention; dyadic, so OBJ's
// 1 − v is exact too). The decoy set 0 maps the same grid elsewhere (x and y swapped).
constexpr int kNt = 16, kNz = 4;
TestMesh cylinder() {
  TestMesh m;
  for (int j = 0; j <= kNz; ++j)
    for (int i = 0; i <= kNt; ++i) {
      const double th = i * (kPiD / 2) / kNt, z = double(j) / kNz;
      m.pos.insert(m.pos.end(), {float(std::cos(th)), float(std::sin(th)), float(z)});
      m.nrm.insert(m.nrm.end(), {float(std::cos(th)), float(std::sin(th)), 0.0f});
      const float x = float(1.0 / 16 + 0.875 * i / kNt), y = float(1.0 / 16 + 0.875 * j / kNz);
      m.lm_uv.insert(m.lm_uv.end(), {x, y});
      m.tex_uv.insert(m.tex_uv.end(), {y, x});
    }
  for (int j = 0; j < kNz; ++j)
    for (int i = 0; i < kNt; ++i) {
      const uint32_t a = uint32_t(j * (kNt + 1) + i), b = a + 1, c = a + kNt + 2, d = a + kNt + 1;
      m.idx.insert(m.idx.end(), {a, b, c, a, c, d});
    }
  return m;
}

// --- The independent reference for "touches" (no clipping) ---

struct P2 {
  double x, y;
};

// Triangle k of `m` in pixel space, computed from the float UVs exactly as the rasteriser does.
std::array<P2, 3> pixel_triangle(const MeshTriangles& m, size_t t, int w, int h) {
  std::array<P2, 3> p;
  for (int k = 0; k < 3; ++k) {
    const uint32_t i = m.indices[t * 3 + size_t(k)];
    p[size_t(k)] = {double(m.uv[i * 2]) * w, (1.0 - double(m.uv[i * 2 + 1])) * h};
  }
  return p;
}

bool strictly_inside(const std::array<P2, 3>& t, double x, double y) {
  double s[3];
  for (int k = 0; k < 3; ++k) {
    const P2 a = t[size_t(k)], b = t[size_t((k + 1) % 3)];
    s[k] = (b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x);
  }
  return (s[0] > 0 && s[1] > 0 && s[2] > 0) || (s[0] < 0 && s[1] < 0 && s[2] < 0);
}

// Segment a→b meets the open square (x0, x0+1) × (y0, y0+1) in more than a point (Liang–Barsky).
bool segment_crosses(P2 a, P2 b, int x0, int y0) {
  double tmin = 0, tmax = 1;
  const double p[2] = {a.x, a.y}, d[2] = {b.x - a.x, b.y - a.y}, lo[2] = {double(x0), double(y0)};
  for (int k = 0; k < 2; ++k) {
    if (d[k] == 0) {
      if (!(p[k] > lo[k] && p[k] < lo[k] + 1)) return false;
      continue;
    }
    double ta = (lo[k] - p[k]) / d[k], tb = (lo[k] + 1 - p[k]) / d[k];
    if (ta > tb) std::swap(ta, tb);
    tmin = std::max(tmin, ta), tmax = std::min(tmax, tb);
  }
  return tmax > tmin;
}

// Touched = a vertex strictly inside the texel, an edge through its interior, or one of 64×64
// sample points strictly inside the triangle (the texel wholly inside it).
bool touches(const std::array<P2, 3>& t, int x, int y) {
  for (int k = 0; k < 3; ++k) {
    const P2 a = t[size_t(k)];
    if (a.x > x && a.x < x + 1 && a.y > y && a.y < y + 1) return true;
    if (segment_crosses(a, t[size_t((k + 1) % 3)], x, y)) return true;
  }
  for (int sy = 0; sy < 64; ++sy)
    for (int sx = 0; sx < 64; ++sx)
      if (strictly_inside(t, x + (sx + 0.5) / 64, y + (sy + 0.5) / 64)) return true;
  return false;
}

// Compares coverage with the reference over the whole image; returns the texels covered.
size_t check_coverage(const MeshTriangles& m, int w, int h, const RasterisedNormals& r, const std::string& what) {
  std::vector<uint8_t> ref(size_t(w) * h, 0);
  for (size_t t = 0; t < m.indices.size() / 3; ++t) {
    const auto p = pixel_triangle(m, t, w, h);
    const double area = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y);
    if (area == 0) continue;
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (const P2& q : p) x0 = std::min(x0, q.x), x1 = std::max(x1, q.x), y0 = std::min(y0, q.y), y1 = std::max(y1, q.y);
    const int ax = int(std::clamp(std::floor(x0), 0.0, double(w - 1))), bx = int(std::clamp(std::floor(x1), 0.0, double(w - 1)));
    const int ay = int(std::clamp(std::floor(y0), 0.0, double(h - 1))), by = int(std::clamp(std::floor(y1), 0.0, double(h - 1)));
    for (int y = ay; y <= by; ++y)
      for (int x = ax; x <= bx; ++x)
        if (!ref[size_t(y) * w + x] && touches(p, x, y)) ref[size_t(y) * w + x] = 1;
  }
  size_t covered = 0, missed = 0, extra = 0;
  for (size_t i = 0; i < ref.size(); ++i) {
    covered += r.coverage[i];
    missed += ref[i] && !r.coverage[i];
    extra += !ref[i] && r.coverage[i];
  }
  EXPECT_EQ(missed, 0u) << what << ": texels a triangle touches left uncovered";
  EXPECT_EQ(extra, 0u) << what << ": texels covered that no triangle touches";
  return covered;
}

// Angle between a and b (atan2 of |a × b| and a · b: acos loses 1e-4 rad near 0).
double angle_to(const float* a, const double b[3]) {
  const double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  return std::atan2(std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]), a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
}

MeshTriangles single(const std::array<P2, 3>& px, int w, int h, const std::array<float, 3>& n = {0, 0, 1}) {
  MeshTriangles m;
  for (const P2& p : px) {
    m.positions.insert(m.positions.end(), {float(p.x), float(p.y), 0});
    m.normals.insert(m.normals.end(), n.begin(), n.end());
    m.uv.insert(m.uv.end(), {float(p.x / w), float(1 - p.y / h)});
  }
  m.indices = {0, 1, 2};
  return m;
}

}  // namespace

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

TEST(MeshRaster, BadMeshesGiveOneClearError) {
  const fs::path d = ahd_test::temp_dir("mesh_bad");
  const TestMesh cyl = cylinder();
  write_obj((d / "c.obj").string(), cyl);
  write_obj((d / "nouv.obj").string(), cyl, true, false);
  std::ofstream(d / "lines.obj") << "v 0 0 0\nv 1 0 0\nvt 0 0\nl 1 2\n";
  std::ofstream(d / "c.fbx") << "x";
  std::ofstream(d / "junk.gltf") << "{ not json";
  using layout_test::expect_error;  // one ahd::Error, one line, naming the cause
  expect_error([&] { read_mesh_lightmap((d / "none.obj").string(), -1); }, "none.obj: file not found");
  expect_error([&] { read_mesh_lightmap((d / "c.obj").string(), 1); }, "UV set 1 requested, mesh");
  expect_error([&] { read_mesh_lightmap((d / "c.obj").string(), 1); }, "has 1 UV set (0..0)");
  expect_error([&] { read_mesh_lightmap((d / "nouv.obj").string(), -1); }, "has no UVs");
  expect_error([&] { read_mesh_lightmap((d / "lines.obj").string(), -1); }, "lines.obj: no triangles");
  expect_error([&] { read_mesh_lightmap((d / "c.fbx").string(), -1); }, "unsupported mesh format '.fbx'");
  expect_error([&] { read_mesh_lightmap((d / "junk.gltf").string(), -1); }, "junk.gltf: cannot read mesh");

  // The command line: one line, non-zero exit, nothing written.
  BakerOptions bo;
  bo.width = bo.height = 8;
  bo.coeffs = 4;
  const ShImage sh = bake_analytic_scene(bo);
  ImageF packed(8, 32, 3), normals(8, 8, 3);
  for (size_t i = 0; i < sh.texels(); ++i)
    for (int c = 0; c < 3; ++c) {
      packed.data[i * 3 + size_t(c)] = sh.texel(i)[c];
      for (int k = 1; k < 4; ++k) packed.data[(i + size_t(k) * 64) * 3 + size_t(c)] = 0.5f;
      normals.data[i * 3 + 2] = 1;
    }
  write_image((d / "lm.exr").string(), packed, true);
  write_image((d / "n.exr").string(), normals);
  const std::string out = (d / "out" / "a.ktx2").string();
  auto fails = [&](std::vector<std::string> extra, const std::string& needle) {
    std::vector<std::string> args = {"convert", (d / "lm").string(), "--layout", "godot4-packed", "-o", out};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = ahd_test::run_cli(args);
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_NE(r.output.find(needle), std::string::npos) << "expected '" << needle << "' in: " << r.output;
    EXPECT_FALSE(fs::exists(d / "out")) << "output written";
  };
  fails({"--mesh", (d / "none.obj").string()}, "none.obj: file not found");
  fails({"--mesh", (d / "c.obj").string(), "--uv-set", "1"}, "has 1 UV set");
  fails({"--mesh", (d / "nouv.obj").string()}, "has no UVs");
  fails({"--mesh", (d / "c.obj").string(), "--normals", (d / "n.exr").string()}, "--mesh and --normals");
  fails({"--uv-set", "1", "--normals", (d / "n.exr").string()}, "--uv-set needs --mesh");
  // A chart outside the image (UVs of the decoy range shifted away): refused, not a black map.
  TestMesh away = cyl;
  for (float& v : away.lm_uv) v += 3;
  write_obj((d / "away.obj").string(), away);
  fails({"--mesh", (d / "away.obj").string()}, "no triangle covers any texel");
  // Sanity: the same command with a good mesh succeeds (so the failures above are the inputs').
  const auto ok = ahd_test::run_cli({"convert", (d / "lm").string(), "--layout", "godot4-packed", "--mesh",
                                     (d / "c.obj").string(), "-o", out, "-q"});
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  fs::remove_all(d);
}

namespace {

// The layout tests' scene: floor chart on the left half (n = +y), wall on the right (n = +z),
// 16×16 with a 1-texel gutter around each chart.
constexpr int kN = layout_test::N;

// The layout tests' scene (layout_test_scene.h), stored Godot-packed, and its normal map.
void write_godot_packed_scene(const std::string& lm, const std::string& normals_exr) {
  const layout_test::WorldScene w = layout_test::world_scene();
  layout_test::write_godot_packed(w, lm);
  write_image(normals_exr, w.normals);
}

// Two quads whose lightmap charts are the scene's (x ∈ [1, 7] and [9, 15], y ∈ [1, 15] texels)
// with the baker's world placement: floor p = (−1 + 2u, 0, 2v), wall p = (−1 + 2u, 2 − 2v, 0).
TestMesh floor_and_wall() {
  TestMesh m;
  for (int wall = 0; wall < 2; ++wall) {
    const uint32_t base = uint32_t(m.verts());
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) {
        if (wall) m.pos.insert(m.pos.end(), {float(-1 + 2 * i), float(2 - 2 * j), 0.0f});
        else m.pos.insert(m.pos.end(), {float(-1 + 2 * i), 0.0f, float(2 * j)});
        m.nrm.insert(m.nrm.end(), {0.0f, wall ? 0.0f : 1.0f, wall ? 1.0f : 0.0f});
        const float x0 = wall ? 9 : 1;
        m.lm_uv.insert(m.lm_uv.end(), {(x0 + 6 * i) / kN, (1.0f + 14 * j) / kN});
      }
    m.idx.insert(m.idx.end(), {base, base + 2, base + 3, base, base + 3, base + 1});
  }
  return m;
}

std::vector<char> bytes(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

}  // namespace

TEST(MeshRaster, ConvertWithMeshEqualsConvertWithTheNormalMap) {
  const fs::path d = ahd_test::temp_dir("mesh_e2e");
  write_godot_packed_scene((d / "lm.exr").string(), (d / "n.exr").string());
  const TestMesh fw = floor_and_wall();
  write_obj((d / "m.obj").string(), fw);
  write_gltf((d / "m.gltf").string(), fw);
  // The rasterised normals are the normal map's on the charts, and the coverage is the charts'.
  const RasterisedNormals r = rasterise_lightmap_normals(read_mesh_lightmap((d / "m.obj").string(), -1), kN, kN);
  const ImageF n = read_image((d / "n.exr").string());
  size_t covered = 0;
  for (int y = 0; y < kN; ++y)
    for (int x = 0; x < kN; ++x) {
      const size_t i = size_t(y) * kN + x;
      const bool chart = y >= 1 && y < kN - 1 && ((x >= 1 && x < 7) || (x >= 9 && x < 15));
      EXPECT_EQ(r.coverage[i], chart ? 1 : 0) << x << "," << y;
      covered += r.coverage[i];
      if (!chart) continue;
      for (int a = 0; a < 3; ++a) EXPECT_EQ(r.normals[i * 3 + size_t(a)], n.at(x, y)[a]) << x << "," << y;
    }
  EXPECT_EQ(covered, 2u * 6 * 14);

  auto convert = [&](const std::string& tag, std::vector<std::string> extra) {
    std::vector<std::string> args = {"convert", (d / "lm").string(), "--layout", "godot4-packed", "-o",
                                     (d / tag / "a.ktx2").string(), "-q"};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto res = ahd_test::run_cli(args);
    EXPECT_EQ(res.exit_code, 0) << res.output;
  };
  convert("normals", {"--normals", (d / "n.exr").string()});
  convert("obj", {"--mesh", (d / "m.obj").string()});
  convert("gltf", {"--mesh", (d / "m.gltf").string()});
  // Bit-exact: the same normals on every covered texel and the same coverage (the mesh's charts
  // are where the SH is non-zero), so the fit, dilation and encoding see identical inputs.
  for (const char* plane : {"iz", "dir", "ratio"}) {
    auto file = [&](const char* tag) { return fs::path(ahd_test::plane_file((d / tag / "a.json").string(), plane)); };
    const auto ref = bytes(file("normals"));
    ASSERT_GT(ref.size(), 100u) << plane;
    EXPECT_TRUE(bytes(file("obj")) == ref) << plane << " differs (obj)";
    EXPECT_TRUE(bytes(file("gltf")) == ref) << plane << " differs (gltf)";
  }
  // A tangent-space layout takes the mesh's coverage only: a flat map, non-zero everywhere
  // (all texels covered without the mesh), is covered exactly on the mesh's charts.
  ImageF flat(kN, kN, 3);
  std::fill(flat.data.begin(), flat.data.end(), 0.3f);
  write_image((d / "flat.exr").string(), flat);
  for (bool mesh : {false, true}) {
    std::vector<std::string> args = {"convert", (d / "flat").string(), "--layout", "plain", "--coverage-plane", "-o",
                                     (d / "plain" / "p.ktx2").string(), "-q"};
    if (mesh) args.insert(args.end(), {"--mesh", (d / "m.obj").string()});
    const auto res = ahd_test::run_cli(args);
    ASSERT_EQ(res.exit_code, 0) << res.output;
    const Texture cov = read_container_file(ahd_test::plane_file((d / "plain" / "p.json").string(), "coverage"));
    ASSERT_EQ(cov.levels[0].data.size(), size_t(kN * kN));
    for (size_t i = 0; i < r.coverage.size(); ++i)
      EXPECT_EQ(cov.levels[0].data[i], mesh ? r.coverage[i] * 255 : 255) << i;
  }
  fs::remove_all(d);
}

// Unity-world bakers (Bakery) are left-handed; a mesh exported to glTF/OBJ has x negated. The
// preset's mesh_axes brings the mesh's normals into the baker's world: the same planes as the
// baker's own normal map, and different ones without the key.
TEST(MeshRaster, MeshAxesBringGltfNormalsIntoTheBakersWorld) {
  const fs::path d = ahd_test::temp_dir("mesh_axes");
  const layout_test::WorldScene w = layout_test::world_scene();
  layout_test::write_bakery_sh(w, (d / "lm").string());
  // Tilted charts (normals with an x component), in glTF axes on the mesh…
  TestMesh m = floor_and_wall();
  for (size_t v = 0; v < m.verts(); ++v) {
    const bool wall = m.nrm[v * 3 + 2] > 0.5f;
    const float n[3] = {wall ? -0.6f : 0.6f, wall ? 0.0f : 0.8f, wall ? 0.8f : 0.0f};
    std::copy(n, n + 3, &m.nrm[v * 3]);
  }
  write_obj((d / "m.obj").string(), m);
  // …and in Unity's axes (x negated) in the baker's normal map.
  ImageF nmap(kN, kN, 3);
  for (int y = 0; y < kN; ++y)
    for (int x = 0; x < kN; ++x) {
      const bool wall = x >= kN / 2;
      const float n[3] = {wall ? 0.6f : -0.6f, wall ? 0.0f : 0.8f, wall ? 0.8f : 0.0f};
      std::copy(n, n + 3, nmap.at(x, y));
    }
  write_image((d / "n.exr").string(), nmap);
  // The same preset without mesh_axes.
  std::ifstream in(std::string(AHD_SOURCE_DIR) + "/formats/bakers/bakery-sh.json");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t at = text.find("  \"mesh_axes\"");
  ASSERT_NE(at, std::string::npos);
  text.erase(at, text.find('\n', at) - at + 1);
  std::ofstream((d / "no-axes.json").string()) << text;

  auto convert = [&](const std::string& tag, const std::string& layout, std::vector<std::string> extra) {
    std::vector<std::string> args = {"convert", (d / "lm").string(), "--layout", layout, "--direction", "keep",
                                     "-o", (d / tag / "a.ktx2").string(), "-q"};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto res = ahd_test::run_cli(args);
    EXPECT_EQ(res.exit_code, 0) << res.output;
  };
  // The normal map covers every texel; the mesh only its charts: give the map the same coverage.
  convert("map", "bakery-sh", {"--normals", (d / "n.exr").string()});
  convert("mesh", "bakery-sh", {"--mesh", (d / "m.obj").string()});
  convert("mesh-no-axes", (d / "no-axes.json").string(), {"--mesh", (d / "m.obj").string()});
  auto dir_plane = [&](const char* tag) { return fs::path(ahd_test::plane_file((d / tag / "a.json").string(), "dir")); };
  const auto ref = bytes(dir_plane("map")), with = bytes(dir_plane("mesh")), without = bytes(dir_plane("mesh-no-axes"));
  ASSERT_GT(ref.size(), 100u);
  EXPECT_TRUE(with == ref) << "mesh normals not brought into the baker's axes";
  EXPECT_FALSE(without == ref) << "mesh_axes has no effect";

  // The key itself: signed axes, each once.
  LayoutPreset bakery = load_layout("bakery-sh");
  std::vector<float> n = {0.6f, 0.0f, 0.8f};
  mesh_normals_to_layout_axes(bakery, &n);
  EXPECT_EQ(n, (std::vector<float>{-0.6f, 0.0f, 0.8f}));
  std::ofstream((d / "bad.json").string())
      << R"({"name":"bad","coeffs":4,"space":"world","mesh_axes":["x","x","z"],"files":[{"pattern":"{base}.exr"}],)"
      << R"("coefficients":[{"file":0}]})";
  layout_test::expect_error([&] { load_layout((d / "bad.json").string()); }, "mesh_axes must name x, y and z once each");
  fs::remove_all(d);
}
