// What the mesh-raster tests share (tests/unit and tests/integration mesh_raster_test.cpp): test
// meshes written as OBJ and glTF.
#pragma once
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

namespace ahd_fixture::mesh_raster_fixture {

namespace fs = std::filesystem;
using namespace ::ahd;

constexpr double kPiD = 3.14159265358979323846;

// A test mesh; UVs in the image convention (v down = glTF's): writers convert for OBJ.
struct TestMesh {
  std::vector<float> pos, nrm, lm_uv, tex_uv;  // tex_uv: a decoy set 0 for glTF (empty = none)
  std::vector<uint32_t> idx;
  size_t verts() const { return pos.size() / 3; }
};

inline MeshTriangles to_triangles(const TestMesh& m) {
  MeshTriangles t{m.pos, m.nrm, m.lm_uv, m.idx};
  for (size_t i = 1; i < t.uv.size(); i += 2) t.uv[i] = 1.0f - t.uv[i];  // to the OBJ convention
  return t;
}

inline void write_obj(const std::string& path, const TestMesh& m, bool normals = true, bool uvs = true) {
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

inline std::string mesh_base64(const std::vector<uint8_t>& d) {
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
inline void write_gltf(const std::string& path, const TestMesh& m, const std::array<double, 4>& rotation = {0, 0, 0, 1}) {
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
inline TestMesh cylinder() {
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
inline std::array<P2, 3> pixel_triangle(const MeshTriangles& m, size_t t, int w, int h) {
  std::array<P2, 3> p;
  for (int k = 0; k < 3; ++k) {
    const uint32_t i = m.indices[t * 3 + size_t(k)];
    p[size_t(k)] = {double(m.uv[i * 2]) * w, (1.0 - double(m.uv[i * 2 + 1])) * h};
  }
  return p;
}

inline bool strictly_inside(const std::array<P2, 3>& t, double x, double y) {
  double s[3];
  for (int k = 0; k < 3; ++k) {
    const P2 a = t[size_t(k)], b = t[size_t((k + 1) % 3)];
    s[k] = (b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x);
  }
  return (s[0] > 0 && s[1] > 0 && s[2] > 0) || (s[0] < 0 && s[1] < 0 && s[2] < 0);
}

// Segment a→b meets the open square (x0, x0+1) × (y0, y0+1) in more than a point (Liang–Barsky).
inline bool segment_crosses(P2 a, P2 b, int x0, int y0) {
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
inline bool touches(const std::array<P2, 3>& t, int x, int y) {
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
inline size_t check_coverage(const MeshTriangles& m, int w, int h, const RasterisedNormals& r, const std::string& what) {
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
inline double angle_to(const float* a, const double b[3]) {
  const double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  return std::atan2(std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]), a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
}

inline MeshTriangles single(const std::array<P2, 3>& px, int w, int h, const std::array<float, 3>& n = {0, 0, 1}) {
  MeshTriangles m;
  for (const P2& p : px) {
    m.positions.insert(m.positions.end(), {float(p.x), float(p.y), 0});
    m.normals.insert(m.normals.end(), n.begin(), n.end());
    m.uv.insert(m.uv.end(), {float(p.x / w), float(1 - p.y / h)});
  }
  m.indices = {0, 1, 2};
  return m;
}

}  // namespace ahd_fixture::mesh_raster_fixture
