// Godot 4 ArrayMesh resources decoded without Godot (bakers/godot/godot_array_mesh): surfaces built
// here byte by byte from the format facts (servers/rendering_server.cpp, both vertex layouts: the
// Godot 4.0/4.1 interleaved stream that Godot 4.6 no longer writes, and 4.2+ with and without
// compressed attributes), written in both PackedByteArray syntaxes, as .tres text, as a binary .res
// and inline in a .tscn; the refusals of bad input; and, when the Godot-generated fixtures exist
// (tests/data/godot/generated/arraymesh.json), the arrays Godot itself returns for the same files.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bakers/godot/godot_array_mesh.h"
#include "core/error.h"
#include "test_data.h"

namespace fs = std::filesystem;
using namespace ahd;

namespace {

// The format bits (servers/rendering/rendering_server.h).
constexpr uint64_t V = 1, N = 2, T = 4, C = 8, UV = 16, UV2 = 32, CUSTOM0 = 64, CUSTOM1 = 128, BONES = 1024,
                   WEIGHTS = 2048, INDEX = 4096;
constexpr uint64_t kCustom0RgbaHalf = 3ull << 13, kCustom1RgbFloat = 6ull << 16;
constexpr uint64_t k2d = 1ull << 25, k8Bones = 1ull << 27, kCompress = 1ull << 29, kVersion2 = 1ull << 35;

struct Spec {
  uint64_t format = 0;
  int primitive = 3;
  uint32_t vertex_count = 0;
  std::vector<uint8_t> vertex, attribute, skin, index;
  uint32_t index_count = 0;
  double aabb[6] = {0, 0, 0, 1, 1, 1};
  double uv_scale[4] = {0, 0, 0, 0};
};

void put16(std::vector<uint8_t>& b, uint32_t v) { b.push_back(uint8_t(v)), b.push_back(uint8_t(v >> 8)); }
void put32(std::vector<uint8_t>& b, uint32_t v) { put16(b, v & 0xFFFF), put16(b, v >> 16); }
void putf(std::vector<uint8_t>& b, float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  put32(b, u);
}

// Vector3::octahedron_encode as _surface_set_data stores it (CLAMP(x * 65535), truncated).
uint32_t oct(double x, double y, double z) {
  const double l = std::fabs(x) + std::fabs(y) + std::fabs(z);
  x /= l, y /= l, z /= l;
  double ox = x, oy = y;
  if (z < 0) ox = (1 - std::fabs(y)) * (x >= 0 ? 1 : -1), oy = (1 - std::fabs(x)) * (y >= 0 ? 1 : -1);
  const auto q = [](double o) { return uint32_t(std::clamp((o * 0.5 + 0.5) * 65535, 0.0, 65535.0)); };
  return q(ox) | q(oy) << 16;
}
// The inverse, in double (an independent implementation of octahedron_decode).
void unoct(uint32_t p, double n[3]) {
  const double fx = (p & 0xFFFF) / 65535.0 * 2 - 1, fy = (p >> 16) / 65535.0 * 2 - 1;
  double x = fx, y = fy, z = 1 - std::fabs(fx) - std::fabs(fy);
  const double t = std::clamp(-z, 0.0, 1.0);
  x += x >= 0 ? -t : t, y += y >= 0 ? -t : t;
  const double l = std::sqrt(x * x + y * y + z * z);
  n[0] = x / l, n[1] = y / l, n[2] = z / l;
}

// A quad in the z = 0.5 plane facing +z, UV2 in a corner of the atlas, two triangles.
const float kPos[4][3] = {{-1, -1, 0.5f}, {1, -1, 0.5f}, {1, 1, 0.5f}, {-1, 1, 0.5f}};
const float kUv2[4][2] = {{0.125f, 0.75f}, {0.375f, 0.75f}, {0.375f, 0.5f}, {0.125f, 0.5f}};  // Godot's v down
const double kNormal[4][3] = {{0, 0, 1}, {0.6, 0, 0.8}, {0, -0.6, 0.8}, {-0.48, 0.36, 0.8}};
const uint16_t kIdx[6] = {0, 1, 2, 0, 2, 3};

std::vector<uint8_t> quad_indices() {
  std::vector<uint8_t> b;
  for (uint16_t i : kIdx) put16(b, i);
  return b;
}

// The quad in Godot 4.2+'s uncompressed layout, with `extra` attribute arrays (C, UV, custom).
Spec quad_v2(uint64_t extra = UV) {
  Spec s;
  s.format = V | N | T | UV2 | INDEX | extra | kVersion2;
  s.vertex_count = 4;
  for (auto& p : kPos) putf(s.vertex, p[0]), putf(s.vertex, p[1]), putf(s.vertex, p[2]);
  for (auto& n : kNormal) put32(s.vertex, oct(n[0], n[1], n[2])), put32(s.vertex, 0x9ABC1234u);  // normal, tangent
  for (int i = 0; i < 4; ++i) {
    if (extra & C) put32(s.attribute, 0xFF00FF00u);
    if (extra & UV) putf(s.attribute, 7.0f + i), putf(s.attribute, -3.0f);
    putf(s.attribute, kUv2[i][0]), putf(s.attribute, kUv2[i][1]);
    if (extra & CUSTOM0) put32(s.attribute, 0x11111111u), put32(s.attribute, 0x22222222u);
    if (extra & CUSTOM1) putf(s.attribute, 1), putf(s.attribute, 2), putf(s.attribute, 3);
  }
  s.index = quad_indices();
  s.index_count = 6;
  s.aabb[0] = -1, s.aabb[1] = -1, s.aabb[2] = 0.5, s.aabb[3] = 2, s.aabb[4] = 2, s.aabb[5] = 1e-5;
  return s;
}

// The same quad as Godot 4.0/4.1 stored it: format version 1, one interleaved vertex stream
// (position, normal, tangent per vertex; fix_surface_compatibility).
Spec quad_v1() {
  Spec s = quad_v2();
  s.format &= ~kVersion2;
  s.vertex.clear();
  for (int i = 0; i < 4; ++i) {
    putf(s.vertex, kPos[i][0]), putf(s.vertex, kPos[i][1]), putf(s.vertex, kPos[i][2]);
    put32(s.vertex, oct(kNormal[i][0], kNormal[i][1], kNormal[i][2])), put32(s.vertex, 0x9ABC1234u);
  }
  return s;
}

std::string base64(const std::vector<uint8_t>& b) {
  static const char* a = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string o;
  for (size_t i = 0; i < b.size(); i += 3) {
    const uint32_t v =
        uint32_t(b[i]) << 16 | (i + 1 < b.size() ? b[i + 1] << 8 : 0) | (i + 2 < b.size() ? b[i + 2] : 0);
    o += a[v >> 18], o += a[(v >> 12) & 63];
    o += i + 1 < b.size() ? a[(v >> 6) & 63] : '=';
    o += i + 2 < b.size() ? a[v & 63] : '=';
  }
  return o;
}

std::string bytes_text(const std::vector<uint8_t>& b, bool b64) {
  if (b64) return b.empty() ? "PackedByteArray()" : "PackedByteArray(\"" + base64(b) + "\")";
  std::string s = "PackedByteArray(";
  for (size_t i = 0; i < b.size(); ++i) s += (i ? ", " : "") + std::to_string(b[i]);
  return s + ")";
}

std::string num(double d) {
  std::ostringstream o;
  o.precision(9);
  o << d;
  return o.str();
}

// `_surfaces` as Godot's text saver writes it (keys sorted, one per line).
std::string surfaces_text(const std::vector<Spec>& specs, bool b64) {
  std::string t = "[";
  for (size_t k = 0; k < specs.size(); ++k) {
    const Spec& s = specs[k];
    t += k ? ", {\n" : "{\n";
    t += "\"aabb\": AABB(" + num(s.aabb[0]) + ", " + num(s.aabb[1]) + ", " + num(s.aabb[2]) + ", " + num(s.aabb[3]) +
         ", " + num(s.aabb[4]) + ", " + num(s.aabb[5]) + "),\n";
    if (!s.attribute.empty()) t += "\"attribute_data\": " + bytes_text(s.attribute, b64) + ",\n";
    t += "\"format\": " + std::to_string(s.format) + ",\n";
    if (!s.index.empty()) {
      t += "\"index_count\": " + std::to_string(s.index_count) + ",\n";
      t += "\"index_data\": " + bytes_text(s.index, b64) + ",\n";
    }
    t += "\"material\": SubResource(\"StandardMaterial3D_x1\"),\n\"name\": \"surface \\\"a\\\"\",\n";
    t += "\"primitive\": " + std::to_string(s.primitive) + ",\n";
    if (!s.skin.empty()) t += "\"skin_data\": " + bytes_text(s.skin, b64) + ",\n";
    t += "\"uv_scale\": Vector4(" + num(s.uv_scale[0]) + ", " + num(s.uv_scale[1]) + ", " + num(s.uv_scale[2]) + ", " +
         num(s.uv_scale[3]) + "),\n";
    t += "\"vertex_count\": " + std::to_string(s.vertex_count) + ",\n";
    t += "\"vertex_data\": " + bytes_text(s.vertex, b64) + "\n}";
  }
  return t + "]";
}

// A binary resource (.res / .mesh) holding one ArrayMesh, as ResourceFormatSaverBinary lays it out
// (core/io/resource_format_binary.cpp): header, string table, no external resources, one internal
// resource (the main one) with its `_surfaces` array of dictionaries.
struct Bin {
  std::vector<uint8_t> b;
  void u32(uint32_t v) { put32(b, v); }
  void u64(uint64_t v) { u32(uint32_t(v)), u32(uint32_t(v >> 32)); }
  void str(const std::string& s) {
    u32(uint32_t(s.size() + 1));
    b.insert(b.end(), s.begin(), s.end());
    b.push_back(0);
  }
  void key(const std::string& s) { u32(5), str(s); }
  void bytes(const std::vector<uint8_t>& d) {
    u32(31), u32(uint32_t(d.size()));
    b.insert(b.end(), d.begin(), d.end());
    b.insert(b.end(), (4 - d.size() % 4) % 4, 0);  // padded to 4 bytes (of the data, not the file)
  }
};

std::string binary_mesh(const std::vector<Spec>& specs, uint32_t format = 6, const std::string& type = "ArrayMesh") {
  Bin o;
  o.b = {'R', 'S', 'R', 'C'};
  o.u32(0), o.u32(0), o.u32(4), o.u32(6), o.u32(format);
  o.str(type);
  o.u64(0);      // import metadata
  o.u32(1 | 2);  // named scene ids, uids
  o.u64(0x1234567890ull);
  for (int i = 0; i < 11; ++i) o.u32(0);
  o.u32(2), o.str("_surfaces"), o.str("blend_shape_mode");
  o.u32(0);  // external resources
  o.u32(1), o.str("local://1");
  const size_t patch = o.b.size();
  o.u64(0);
  const uint64_t at = o.b.size();
  for (int k = 0; k < 8; ++k) o.b[patch + k] = uint8_t(at >> (8 * k));
  o.str(type);
  o.u32(2);
  o.u32(1), o.u32(3), o.u32(0);  // blend_shape_mode = 0
  o.u32(0), o.u32(30), o.u32(uint32_t(specs.size()));
  for (const Spec& s : specs) {
    o.u32(26), o.u32(s.index.empty() ? 7 : 9);
    o.key("aabb"), o.u32(15);
    for (double a : s.aabb) putf(o.b, float(a));
    o.key("attribute_data"), o.bytes(s.attribute);
    o.key("format"), o.u32(40), o.u64(s.format);
    if (!s.index.empty()) o.key("index_count"), o.u32(3), o.u32(s.index_count), o.key("index_data"), o.bytes(s.index);
    o.key("primitive"), o.u32(3), o.u32(uint32_t(s.primitive));
    o.key("uv_scale"), o.u32(50);
    for (double u : s.uv_scale) putf(o.b, float(u));
    o.key("vertex_count"), o.u32(3), o.u32(s.vertex_count);
    o.key("vertex_data"), o.bytes(s.vertex);
  }
  return std::string(o.b.begin(), o.b.end());
}

void expect_same(const MeshTriangles& a, const MeshTriangles& b) {
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.normals, b.normals);
  EXPECT_EQ(a.uv, b.uv);
  EXPECT_EQ(a.indices, b.indices);
}

void expect_quad(const MeshTriangles& m, double normal_tolerance = 1e-4) {
  ASSERT_EQ(m.positions.size(), 12u);
  ASSERT_EQ(m.uv.size(), 8u);
  ASSERT_EQ(m.normals.size(), 12u);
  for (int i = 0; i < 4; ++i) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(m.positions[i * 3 + k], kPos[i][k]) << i;
    EXPECT_EQ(m.uv[i * 2], kUv2[i][0]) << i;
    EXPECT_EQ(m.uv[i * 2 + 1], 1.0f - kUv2[i][1]) << i;  // v up
    // 16-bit octahedral: each stored coordinate within 1/65535 of the exact one → ≲ 1e-4.
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(m.normals[i * 3 + k], kNormal[i][k], normal_tolerance) << i;
  }
  EXPECT_EQ(m.indices, std::vector<uint32_t>(kIdx, kIdx + 6));
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(GodotArrayMesh, UncompressedLayoutInBothByteArraySyntaxes) {
  const Spec s = quad_v2();
  const MeshTriangles numbers = godot_array_mesh_text(surfaces_text({s}, false), "a.tscn");
  expect_quad(numbers);
  // The normals are exactly an independent double decode of the stored bits, rounded to float.
  for (int i = 0; i < 4; ++i) {
    double n[3];
    unoct(oct(kNormal[i][0], kNormal[i][1], kNormal[i][2]), n);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(numbers.normals[i * 3 + k], n[k], 1e-6);
  }
  const MeshTriangles b64 = godot_array_mesh_text(surfaces_text({s}, true), "a.tscn");
  expect_same(numbers, b64);
}

TEST(GodotArrayMesh, Godot40InterleavedLayoutDecodesLikeTheNewOne) {
  const MeshTriangles v1 = godot_array_mesh_text(surfaces_text({quad_v1()}, false), "old.tres");
  expect_quad(v1);
  expect_same(v1, godot_array_mesh_text(surfaces_text({quad_v2()}, false), "new.tres"));
  // Version 1 without normals/tangents: 12 bytes a vertex.
  Spec bare = quad_v1();
  bare.format &= ~(N | T);
  bare.vertex.clear();
  for (auto& p : kPos) putf(bare.vertex, p[0]), putf(bare.vertex, p[1]), putf(bare.vertex, p[2]);
  const MeshTriangles m = godot_array_mesh_text(surfaces_text({bare}, true), "old.tres");
  EXPECT_TRUE(m.normals.empty());
  EXPECT_EQ(m.positions, v1.positions);
  EXPECT_EQ(m.uv, v1.uv);
}

TEST(GodotArrayMesh, AttributeStridesWithColourUvCustomAndSkin) {
  // Colour (4) + UV (8) + UV2 (8) + custom0 RGBA half (8) + custom1 RGB float (12) = 40 bytes a
  // vertex, UV2 at 12; bones and weights (8 each with 8 weights: 16) in the skin stream.
  Spec s = quad_v2(C | UV | CUSTOM0 | CUSTOM1 | kCustom0RgbaHalf | kCustom1RgbFloat);
  ASSERT_EQ(s.attribute.size(), 4u * 40);
  s.format |= BONES | WEIGHTS | k8Bones;
  s.skin.assign(4 * 32, 1);
  expect_quad(godot_array_mesh_text(surfaces_text({s}, false), "a.tres"));
  // Read with the wrong custom type the strides disagree with the data: refused, not misread.
  Spec wrong = s;
  wrong.format &= ~kCustom1RgbFloat;
  EXPECT_NE(error_of([&] {
              godot_array_mesh_text(surfaces_text({wrong}, false), "a.tres");
            }).find("attribute_data holds 160 bytes"),
            std::string::npos);
}

TEST(GodotArrayMesh, CompressedPositionsNormalsAndUv2) {
  // Godot 4.2+ with ARRAY_FLAG_COMPRESS_ATTRIBUTES: positions 16-bit in the AABB with the
  // tangent-frame angle in the 4th word, the frame's axis octahedral in the normal stream, UV2
  // 16-bit (scaled by uv_scale.zw around 0.5 when uv_scale is not zero).
  Spec s;
  s.format = V | N | T | UV2 | INDEX | kCompress | kVersion2;
  s.vertex_count = 3;
  s.aabb[0] = -2, s.aabb[1] = 1, s.aabb[2] = 10, s.aabb[3] = 4, s.aabb[4] = 0.5, s.aabb[5] = 3;
  const uint16_t q[3][3] = {{0, 0, 0}, {65535, 32768, 100}, {12345, 65535, 54321}};
  const double axis[3][3] = {{0, 0, 1}, {1, 2, 3}, {-0.3, 0.1, -0.9}};
  const double angle_in[3] = {0.0, 1.0, 2.5};  // radians
  uint16_t stored_angle[3];
  for (int i = 0; i < 3; ++i) {
    // p > 0.5: binormal sign +, angle = (2p − 1)·π (_get_tbn_from_axis_angle).
    stored_angle[i] = uint16_t(std::lround((0.5 + angle_in[i] / (2 * M_PI)) * 65535));
    put16(s.vertex, q[i][0]), put16(s.vertex, q[i][1]), put16(s.vertex, q[i][2]), put16(s.vertex, stored_angle[i]);
  }
  uint32_t stored_axis[3];
  for (int i = 0; i < 3; ++i) put32(s.vertex, stored_axis[i] = oct(axis[i][0], axis[i][1], axis[i][2]));
  const uint16_t uvq[3][2] = {{0, 65535}, {32768, 16384}, {65535, 0}};
  for (auto& u : uvq) put16(s.attribute, u[0]), put16(s.attribute, u[1]);
  s.index = {0, 0, 1, 0, 2, 0};
  s.index_count = 3;
  for (bool scaled : {false, true}) {
    if (scaled) s.uv_scale[2] = 4, s.uv_scale[3] = 2;
    const MeshTriangles m = godot_array_mesh_text(surfaces_text({s}, scaled), "c.tscn");
    ASSERT_EQ(m.positions.size(), 9u);
    ASSERT_EQ(m.normals.size(), 9u);
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(m.positions[i * 3 + k], q[i][k] / 65535.0 * s.aabb[3 + k] + s.aabb[k], 2e-6);
      for (int k = 0; k < 2; ++k) {
        const double u = uvq[i][k] / 65535.0;
        const double want = scaled ? (u - 0.5) * s.uv_scale[2 + k] : u;
        EXPECT_NEAR(m.uv[i * 2 + k], k ? 1 - want : want, 1e-6);
      }
      // The normal: row 2 of the axis-angle rotation (Rodrigues), in double from the stored bits.
      double a[3];
      unoct(stored_axis[i], a);
      const double th = std::fabs(stored_angle[i] / 65535.0 * 2 - 1) * M_PI, c = std::cos(th), sn = std::sin(th);
      const double want[3] = {a[0] * a[2] * (1 - c) - a[1] * sn, a[1] * a[2] * (1 - c) + a[0] * sn,
                              c + a[2] * a[2] * (1 - c)};
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(m.normals[i * 3 + k], want[k], 2e-6) << i << " " << k;
    }
    // Vertex 0 has angle ~0: its normal is its axis (+z).
    EXPECT_NEAR(m.normals[2], 1.0, 1e-4);
    EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2}));
  }
}

TEST(GodotArrayMesh, IndexWidthFollowsTheVertexCount) {
  // Up to 65536 vertices 16-bit indices, above 32-bit (mesh_surface_get_format_index_stride).
  for (uint32_t count : {65536u, 65537u}) {
    Spec s;
    s.format = V | UV2 | INDEX | kVersion2;
    s.vertex_count = count;
    for (uint32_t i = 0; i < count; ++i) {
      putf(s.vertex, float(i)), putf(s.vertex, 0), putf(s.vertex, 0);
      putf(s.attribute, float(i) / count), putf(s.attribute, 0.25f);
    }
    const uint32_t idx[3] = {0, count - 1, count / 2};
    for (uint32_t i : idx) count > 65536 ? put32(s.index, i) : put16(s.index, i);
    s.index_count = 3;
    const MeshTriangles m = godot_array_mesh_text(surfaces_text({s}, true), "big.tres");
    EXPECT_EQ(m.indices, std::vector<uint32_t>(idx, idx + 3)) << count;
    EXPECT_EQ(m.positions[3 * (count - 1)], float(count - 1));
    EXPECT_EQ(m.uv[1], 0.75f);
    EXPECT_TRUE(m.normals.empty());
  }
}

TEST(GodotArrayMesh, SurfacesMergeInOrderAndUnindexedIsSequential) {
  Spec plain;  // no normals, no index array: the vertices in order
  plain.format = V | UV2 | kVersion2;
  plain.vertex_count = 3;
  for (int i = 0; i < 3; ++i) {
    putf(plain.vertex, 5.0f + i), putf(plain.vertex, 0), putf(plain.vertex, 0);
    putf(plain.attribute, 0.5f), putf(plain.attribute, 0.5f);
  }
  const MeshTriangles m = godot_array_mesh_text(surfaces_text({quad_v2(), plain}, false), "two.tscn");
  ASSERT_EQ(m.positions.size(), 21u);
  EXPECT_EQ(m.positions[12], 5.0f);
  ASSERT_EQ(m.normals.size(), 21u);  // the second surface's normals are zero (face normals used)
  for (int k = 12; k < 21; ++k) EXPECT_EQ(m.normals[k], 0.0f);
  EXPECT_NEAR(m.normals[2], 1.0, 1e-4);
  EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 4, 5, 6}));
  EXPECT_TRUE(godot_array_mesh_text("[]", "empty.tres").positions.empty());
}

TEST(GodotArrayMesh, ResourceFilesTextAndBinary) {
  const std::vector<Spec> specs = {quad_v2(), quad_v1()};
  const MeshTriangles want = godot_array_mesh_text(surfaces_text(specs, false), "want");
  ASSERT_EQ(want.indices.size(), 12u);
  const std::string tres =
      "[gd_resource type=\"ArrayMesh\" load_steps=2 format=4 uid=\"uid://b1\"]\n\n"
      "[sub_resource type=\"StandardMaterial3D\" id=\"StandardMaterial3D_x1\"]\n"
      "albedo_color = Color(1, 0, 0, 1)\n; a comment\n\n"
      "[resource]\nresource_name = \"Quad [x]\"\n_surfaces = " +
      surfaces_text(specs, true) + "\nblend_shape_mode = 0\n";
  expect_same(godot_mesh_resource_file(tres, "m.tres"), want);
  for (uint32_t format : {3u, 5u, 6u}) expect_same(godot_mesh_resource_file(binary_mesh(specs, format), "m.res"), want);

  auto refused = [](const std::string& bytes, const std::string& why) {
    const std::string e = error_of([&] { godot_mesh_resource_file(bytes, "bad.mesh"); });
    EXPECT_EQ(e.rfind("bad.mesh: ", 0), 0u) << e;
    EXPECT_NE(e.find(why), std::string::npos) << e;
  };
  refused(binary_mesh(specs, 6, "StandardMaterial3D"), "not an ArrayMesh");
  refused(binary_mesh(specs, 7), "format 7");
  refused("RSCC" + binary_mesh(specs).substr(4), "compressed");
  const std::string bin = binary_mesh(specs);
  refused(bin.substr(0, bin.size() - 9), "not a readable Godot resource");
  refused("[gd_resource type=\"Mesh\" format=3]\n[resource]\n", "not an ArrayMesh");
  refused("[gd_resource type=\"ArrayMesh\" format=3]\n[resource]\nblend_shape_mode = 0\n", "no _surfaces");
  refused("_surfaces = []\n", "no [gd_resource]");
}

TEST(GodotArrayMesh, InlineMeshOfAScene) {
  const std::string tscn =
      "[gd_scene load_steps=4 format=3 uid=\"uid://c\"]\n\n"
      "[ext_resource type=\"Script\" path=\"res://a.gd\" id=\"1_a\"]\n\n"
      "[sub_resource type=\"ArrayMesh\" id=\"ArrayMesh_one\"]\n_surfaces = " +
      surfaces_text({quad_v1()}, false) +
      "\n\n[sub_resource type=\"GDScript\" id=\"GDScript_s\"]\nscript/source = \"extends Node\n"
      "var a = \\\"[sub_resource]\\\"\n\"\n\n"
      "[sub_resource type=\"ArrayMesh\" id=\"ArrayMesh_two\"]\n_surfaces = " +
      surfaces_text({quad_v2()}, true) +
      "\n\n[node name=\"Root\" type=\"Node3D\"]\n\n"
      "[node name=\"CSG\" type=\"MeshInstance3D\" parent=\".\"]\ntransform = Transform3D(1, 0, 0, 0, 1, 0, 0, 0, 1, 0, "
      "0, 0)\n"
      "mesh = SubResource(\"ArrayMesh_two\")\nmetadata/_edit_group_ = true\n";
  const MeshTriangles two = godot_text_sub_resource_mesh(tscn, "ArrayMesh_two", "s.tscn");
  expect_quad(two);
  expect_same(two, godot_text_sub_resource_mesh(tscn, "ArrayMesh_one", "s.tscn"));
  EXPECT_NE(error_of([&] { godot_text_sub_resource_mesh(tscn, "GDScript_s", "s.tscn"); }).find("not an ArrayMesh"),
            std::string::npos);
  EXPECT_NE(error_of([&] { godot_text_sub_resource_mesh(tscn, "nope", "s.tscn"); }).find("no [sub_resource"),
            std::string::npos);
}

TEST(GodotArrayMesh, RefusesBadSurfacesWithOneLine) {
  struct Case {
    std::string what;
    std::function<void(Spec&)> edit;
  };
  const std::vector<Case> cases = {
      {"no lightmap UV2", [](Spec& s) { s.format &= ~UV2; }},
      {"primitive 4", [](Spec& s) { s.primitive = 4; }},
      {"vertex_data holds", [](Spec& s) { s.vertex.pop_back(); }},
      {"vertex_data holds", [](Spec& s) { s.vertex_count = 0x7fffffff; }},
      {"attribute_data holds", [](Spec& s) { s.format &= ~UV; }},
      {"index 9 out of range", [](Spec& s) { s.index[2] = 9; }},
      {"index_data holds", [](Spec& s) { s.index_count = 7; }},
      {"not whole triangles", [](Spec& s) { s.index.resize(8), s.index_count = 4; }},
      {"flag disagree", [](Spec& s) { s.format &= ~INDEX; }},
      {"version 3", [](Spec& s) { s.format = (s.format & ~(0xFFull << 35)) | 2ull << 35; }},
      {"compressed attributes in a Godot 4.0/4.1", [](Spec& s) { s.format = (s.format | kCompress) & ~kVersion2; }},
      {"2D", [](Spec& s) { s.format |= k2d; }},
      {"no vertex positions", [](Spec& s) { s.format &= ~V; }},
  };
  for (const Case& c : cases) {
    Spec s = quad_v2();
    c.edit(s);
    const std::string e = error_of([&] { godot_array_mesh_text(surfaces_text({s}, false), "bad.tscn"); });
    EXPECT_EQ(e.rfind("bad.tscn: surface 0: ", 0), 0u) << c.what << ": " << e;
    EXPECT_NE(e.find(c.what), std::string::npos) << c.what << ": " << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
  // Malformed text.
  const std::string good = surfaces_text({quad_v2()}, true);
  for (const auto& [text, why] : std::vector<std::pair<std::string, std::string>>{
           {"[{\"vertex_data\": PackedByteArray(1, 256)}]", "outside 0..255"},
           {"[{\"vertex_data\": PackedByteArray(\"AAA*\")}]", "not base64"},
           {"[{\"vertex_data\": PackedByteArray(\"AAA\")}]", "multiple of 4"},
           {good.substr(0, good.size() / 2), "line"},
           {std::string(5000, '['), "nested deeper"},
           {good + " x", "after the _surfaces"},
           {"{}", "not an array"},
           {"[{\"format\": 1.5}]", "format is not an integer"},
           {"[{\"aabb\": AABB(1, 2)}]", "aabb is not AABB"},
           {"[{\"format\": 99999999999999999999999}]", "malformed number"},
           {"[{\"format\": 34359738403, \"primitive\": 3, \"vertex_count\": 1, \"aabb\": AABB(0,0,0,1,1,1)}]",
            "missing"},
           {"[1]", "not a dictionary"},
           {"[{\"format\": 34359738403, \"primitive\": 3, \"vertex_count\": -1, \"vertex_data\": PackedByteArray(), "
            "\"aabb\": AABB(0, 0, 0, 1, 1, 1)}]",
            "vertex_count -1"},
       }) {
    const std::string& surfaces = text;  // clang 14: a structured binding cannot be captured
    const std::string e = error_of([&] { godot_array_mesh_text(surfaces, "bad.tscn"); });
    EXPECT_EQ(e.rfind("bad.tscn: ", 0), 0u) << why << ": " << e;
    EXPECT_NE(e.find(why), std::string::npos) << why << ": " << e;
  }
}

// Against Godot 4.6 itself: the arrays its surface_get_arrays returns for the files the judge
// worktree generated (arraymesh.json: per file, per surface "vertex", "normal", "uv2" with v down,
// "index"; float32 values in shortest form, exact once cast to float). Positions and UV2 are stored
// as floats: equal exactly. Normals at 1e-6: we decode the same 16-bit octahedral bits with
// Godot's float arithmetic (the quantisation itself, ≈ 1e-4 from the true normal, is in both);
// measured 2026-12-04 on the 10 Godot 4.6 files: 0 difference in all three.
TEST(GodotArrayMesh, MatchesGodotOnItsOwnFiles) {
  const fs::path dir = ahd_test::test_data("godot/generated");
  const fs::path json = dir / "arraymesh.json";
  if (!fs::exists(json)) GTEST_SKIP() << json.string() << " missing (generated by Godot 4.6 in the godot-judge branch)";
  std::ifstream jf(json);
  const nlohmann::json all = nlohmann::json::parse(jf);
  int files = 0;
  double worst[3] = {0, 0, 0};  // position, UV2, normal: largest |ours − Godot's|
  for (const auto& entry : all) {
    const fs::path file = dir / entry.at("file").get<std::string>();
    SCOPED_TRACE(file.string());
    std::ifstream f(file, std::ios::binary);
    ASSERT_TRUE(f) << file;
    const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    MeshTriangles m;
    if (file.extension() == ".tscn") {
      std::string id = entry.value("id", "");
      std::smatch found;
      static const std::regex kArrayMesh(R"(\[sub_resource type="ArrayMesh" id="([^"]+)\")");
      if (id.empty() && std::regex_search(bytes, found, kArrayMesh)) id = found[1];
      m = godot_text_sub_resource_mesh(bytes, id, file.string());
    } else {
      m = godot_mesh_resource_file(bytes, file.string());
    }
    size_t base = 0, ibase = 0;
    for (const auto& s : entry.at("surfaces")) {
      const std::vector<double> vtx = s.at("vertex"), nrm = s.value("normal", std::vector<double>{}), uv2 = s.at("uv2");
      std::vector<int64_t> idx = s.value("index", std::vector<int64_t>{});
      const size_t n = vtx.size() / 3;
      ASSERT_LE((base + n) * 3, m.positions.size());
      for (size_t i = 0; i < 3 * n; ++i) {
        ASSERT_EQ(m.positions[base * 3 + i], float(vtx[i])) << i;
        worst[0] = std::max(worst[0], double(std::fabs(m.positions[base * 3 + i] - float(vtx[i]))));
      }
      ASSERT_EQ(uv2.size(), 2 * n);
      for (size_t i = 0; i < n; ++i) {
        ASSERT_EQ(m.uv[(base + i) * 2], float(uv2[2 * i])) << i;
        ASSERT_EQ(m.uv[(base + i) * 2 + 1], 1.0f - float(uv2[2 * i + 1])) << i;
        worst[1] = std::max({worst[1], double(std::fabs(m.uv[(base + i) * 2] - float(uv2[2 * i]))),
                             double(std::fabs(m.uv[(base + i) * 2 + 1] - (1.0f - float(uv2[2 * i + 1]))))});
      }
      if (!nrm.empty()) {
        ASSERT_EQ(nrm.size(), 3 * n);
        for (size_t i = 0; i < 3 * n; ++i) {
          ASSERT_NEAR(m.normals[base * 3 + i], nrm[i], 1e-6) << i;
          worst[2] = std::max(worst[2], double(std::fabs(m.normals[base * 3 + i] - float(nrm[i]))));
        }
      }
      if (idx.empty())
        for (size_t i = 0; i < n; ++i) idx.push_back(int64_t(i));
      ASSERT_LE(ibase + idx.size(), m.indices.size());
      for (size_t i = 0; i < idx.size(); ++i) ASSERT_EQ(int64_t(m.indices[ibase + i]), idx[i] + int64_t(base)) << i;
      base += n, ibase += idx.size();
    }
    EXPECT_EQ(base * 3, m.positions.size());
    EXPECT_EQ(ibase, m.indices.size());
    ++files;
  }
  EXPECT_GT(files, 0);
  std::printf("%d files; largest difference to Godot: position %g, UV2 %g, normal %g\n", files, worst[0], worst[1],
              worst[2]);
}
