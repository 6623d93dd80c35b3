// Godot 4 primitive meshes with UV2 (src/bakers/godot/godot_primitives.h): against arrays the real
// Godot 4.6 wrote (tests/data/godot/generated/primitives.json, skipped when absent), and on the
// properties that hold without Godot: vertex/triangle counts from Godot's loops, UV2 charts inside
// the unit square and not overlapping, unit normals wound as Godot winds front faces.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "ahd/types.h"
#include "bakers/godot/godot_primitives.h"
#include "test_data.h"

namespace {

using Props = std::map<std::string, std::string>;
using ahd::godot_primitive_lightmap_size_hint;
using ahd::godot_primitive_mesh;
using ahd::MeshTriangles;

Props with_uv2(Props p) {
  p.emplace("add_uv2", "true");
  return p;
}

struct Case {
  std::string type;
  Props props;
};

// Configurations whose charts Godot lays out without overlap (BoxMesh only with equal width and
// height subdivisions: see BoxFrontChartUsesTheWidthSubdivisionsAsGodotDoes).
std::vector<Case> chart_cases() {
  return {
      {"BoxMesh", with_uv2({})},
      {"BoxMesh", with_uv2({{"size", "Vector3(4, 0.2, 4)"}})},
      {"BoxMesh", with_uv2({{"size", "Vector3(1, 3, 2)"},
                            {"subdivide_width", "2"},
                            {"subdivide_height", "2"},
                            {"subdivide_depth", "1"},
                            {"uv2_padding", "5.0"}})},
      {"PlaneMesh", with_uv2({{"subdivide_width", "3"}, {"subdivide_depth", "2"}})},
      {"PlaneMesh", with_uv2({{"orientation", "0"}, {"center_offset", "Vector3(1, 2, 3)"}})},
      {"QuadMesh", with_uv2({{"size", "Vector2(3, 1.5)"}, {"flip_faces", "true"}})},
      {"PrismMesh", with_uv2({})},
      {"PrismMesh",
       with_uv2(
           {{"left_to_right", "0.0"}, {"subdivide_width", "2"}, {"subdivide_height", "3"}, {"subdivide_depth", "1"}})},
      {"PrismMesh", with_uv2({{"left_to_right", "1.0"}, {"size", "Vector3(2, 1, 3)"}})},
      {"CylinderMesh", with_uv2({})},
      {"CylinderMesh", with_uv2({{"top_radius", "0.0"}, {"bottom_radius", "1.5"}, {"radial_segments", "12"}})},
      {"CylinderMesh", with_uv2({{"top_radius", "2.0"}, {"height", "0.5"}, {"cap_bottom", "false"}})},
      {"CapsuleMesh", with_uv2({})},
      {"CapsuleMesh", with_uv2({{"radius", "0.3"}, {"height", "3.0"}, {"radial_segments", "16"}, {"rings", "2"}})},
      {"SphereMesh", with_uv2({})},
      {"SphereMesh", with_uv2({{"radius", "2.0"}, {"height", "1.0"}, {"is_hemisphere", "true"}})},
      {"SphereMesh", with_uv2({{"radial_segments", "10"}, {"rings", "5"}, {"flip_faces", "true"}})},
      {"TorusMesh", with_uv2({})},
      {"TorusMesh",
       with_uv2({{"inner_radius", "2.0"}, {"outer_radius", "0.5"}, {"rings", "12"}, {"ring_segments", "6"}})},
  };
}

std::string describe(const Case& c) {
  std::string s = c.type + " {";
  for (const auto& [k, v] : c.props) s += " " + k + "=" + v;
  return s + " }";
}

TEST(GodotPrimitives, VertexAndTriangleCountsFollowGodotsFormulas) {
  struct Count {
    Case c;
    size_t vertices, triangles;
  };
  // Counts from Godot's loops: rows of (segments + 1) points, 2 triangles a cell; a box face of
  // w x h subdivisions has (w + 2)(h + 2) points; a prism's front/back first row is one triangle a
  // column (the ridge); a cylinder cap is a centre + (segments + 1) points, one triangle a segment.
  const std::vector<Count> counts = {
      {{"BoxMesh", with_uv2({})}, 24, 12},
      {{"BoxMesh", with_uv2({{"subdivide_width", "2"}, {"subdivide_height", "1"}, {"subdivide_depth", "3"}})},
       2 * (3 * 4 + 3 * 5 + 5 * 4),
       4 * (2 * 3 + 2 * 4 + 4 * 3)},
      {{"BoxMesh", with_uv2({{"subdivide_width", "-3"}})}, 24, 12},  // negative -> 0
      {{"PlaneMesh", with_uv2({{"subdivide_width", "3"}, {"subdivide_depth", "1"}})}, 3 * 5, 2 * 4 * 2},
      {{"QuadMesh", with_uv2({})}, 4, 2},
      {{"PrismMesh", with_uv2({{"subdivide_width", "1"}, {"subdivide_height", "2"}})},
       2 * 4 * 3 + 2 * 4 * 2 + 2 * 3,
       2 * (2 + 2 * 2 * 2) + 2 * 3 * 1 * 2 + 1 * 2 * 2},
      {{"CylinderMesh", with_uv2({{"radial_segments", "8"}, {"rings", "2"}})}, 4 * 9 + 2 * 10, 3 * 8 * 2 + 2 * 8},
      {{"CylinderMesh", with_uv2({{"radial_segments", "8"}, {"rings", "2"}, {"cap_top", "false"}})},
       4 * 9 + 10,
       3 * 8 * 2 + 8},
      {{"CylinderMesh", with_uv2({{"radial_segments", "8"}, {"rings", "2"}, {"top_radius", "0"}})},
       4 * 9 + 10,
       3 * 8 * 2 + 8},  // a cone: no top cap
      {{"CylinderMesh", with_uv2({{"radial_segments", "8"}, {"rings", "-1"}})},
       6 * 9 + 2 * 10,
       5 * 8 * 2 + 2 * 8},  // negative rings ignored: the default 4 stays
      {{"CapsuleMesh", with_uv2({{"radial_segments", "6"}, {"rings", "1"}})}, 3 * 3 * 7, 3 * 2 * 6 * 2},
      {{"SphereMesh", with_uv2({{"radial_segments", "5"}, {"rings", "3"}})}, 5 * 6, 4 * 5 * 2},
      {{"SphereMesh", with_uv2({{"radial_segments", "2"}, {"rings", "3"}})}, 5 * 5, 4 * 4 * 2},    // clamp to 4
      {{"SphereMesh", with_uv2({{"radial_segments", "5"}, {"rings", "0"}})}, 34 * 6, 33 * 5 * 2},  // ignored
      {{"TorusMesh", with_uv2({{"rings", "3"}, {"ring_segments", "4"}})}, 4 * 5, 3 * 4 * 2},
      {{"TorusMesh", with_uv2({{"rings", "2"}, {"ring_segments", "4"}})}, 65 * 5, 64 * 4 * 2},  // ignored
  };
  for (const Count& k : counts) {
    const MeshTriangles m = godot_primitive_mesh(k.c.type, k.c.props, "t.tscn");
    EXPECT_EQ(m.positions.size(), k.vertices * 3) << describe(k.c);
    EXPECT_EQ(m.normals.size(), k.vertices * 3) << describe(k.c);
    EXPECT_EQ(m.uv.size(), k.vertices * 2) << describe(k.c);
    EXPECT_EQ(m.indices.size(), k.triangles * 3) << describe(k.c);
    for (uint32_t i : m.indices) ASSERT_LT(i, k.vertices) << describe(k.c);
  }
}

// Grid samples (kGrid x kGrid over the unit square) strictly inside more than one UV triangle
// (samples on a shared edge belong to neither), and the triangles' UV area summed.
struct Coverage {
  int overlaps = 0;
  double area = 0;
};
Coverage uv_coverage(const MeshTriangles& m) {
  constexpr int kGrid = 192;
  std::vector<uint8_t> hits(kGrid * kGrid, 0);
  Coverage out;
  for (size_t k = 0; k < m.indices.size(); k += 3) {
    const float* a = &m.uv[2 * m.indices[k]];
    const float* b = &m.uv[2 * m.indices[k + 1]];
    const float* d = &m.uv[2 * m.indices[k + 2]];
    const double det = double(b[0] - a[0]) * (d[1] - a[1]) - double(d[0] - a[0]) * (b[1] - a[1]);
    out.area += std::fabs(det) / 2;
    if (std::fabs(det) < 1e-12) continue;
    const double lo_u = std::min({a[0], b[0], d[0]}), hi_u = std::max({a[0], b[0], d[0]});
    const double lo_v = std::min({a[1], b[1], d[1]}), hi_v = std::max({a[1], b[1], d[1]});
    for (int y = std::max(0, int(lo_v * kGrid) - 1); y <= std::min(kGrid - 1, int(hi_v * kGrid) + 1); ++y) {
      for (int x = std::max(0, int(lo_u * kGrid) - 1); x <= std::min(kGrid - 1, int(hi_u * kGrid) + 1); ++x) {
        const double pu = (x + 0.5) / kGrid, pv = (y + 0.5) / kGrid;
        const double l1 = ((pu - a[0]) * (d[1] - a[1]) - (d[0] - a[0]) * (pv - a[1])) / det;
        const double l2 = ((b[0] - a[0]) * (pv - a[1]) - (pu - a[0]) * (b[1] - a[1])) / det;
        const double l0 = 1 - l1 - l2;
        constexpr double e = 1e-6;
        if (l0 > e && l1 > e && l2 > e && hits[y * kGrid + x]++) ++out.overlaps;
      }
    }
  }
  return out;
}

TEST(GodotPrimitives, Uv2ChartsStayInTheUnitSquareWithoutOverlap) {
  for (const Case& c : chart_cases()) {
    const MeshTriangles m = godot_primitive_mesh(c.type, c.props, "t.tscn");
    for (float t : m.uv) {
      ASSERT_GE(t, 0.0f) << describe(c);
      ASSERT_LE(t, 1.0f) << describe(c);
    }
    const Coverage cov = uv_coverage(m);
    EXPECT_LE(cov.area, 1.0) << describe(c);
    EXPECT_GT(cov.area, 0.2) << describe(c);  // the charts use the square, not a corner of it
    EXPECT_EQ(cov.overlaps, 0) << describe(c);
  }
}

TEST(GodotPrimitives, NormalsAreUnitAndFrontFacesAreClockwise) {
  for (const Case& c : chart_cases()) {
    const MeshTriangles m = godot_primitive_mesh(c.type, c.props, "t.tscn");
    for (size_t i = 0; i < m.normals.size(); i += 3) {
      const double l = std::sqrt(double(m.normals[i]) * m.normals[i] + double(m.normals[i + 1]) * m.normals[i + 1] +
                                 double(m.normals[i + 2]) * m.normals[i + 2]);
      ASSERT_NEAR(l, 1.0, 1e-6) << describe(c) << " vertex " << i / 3;
    }
    // Godot's front faces are clockwise: cross(p1 - p0, p2 - p0) points against the normal
    // (flip_faces swaps the winding and negates the normals, so it holds there too).
    int counted = 0;
    for (size_t k = 0; k < m.indices.size(); k += 3) {
      const uint32_t i0 = m.indices[k], i1 = m.indices[k + 1], i2 = m.indices[k + 2];
      double e1[3], e2[3], n[3];
      for (int d = 0; d < 3; ++d) {
        e1[d] = double(m.positions[3 * i1 + d]) - m.positions[3 * i0 + d];
        e2[d] = double(m.positions[3 * i2 + d]) - m.positions[3 * i0 + d];
        n[d] = double(m.normals[3 * i0 + d]) + m.normals[3 * i1 + d] + m.normals[3 * i2 + d];
      }
      const double cr[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                            e1[0] * e2[1] - e1[1] * e2[0]};
      const double len = std::sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
      if (len < 1e-9) continue;  // the poles' collapsed triangles
      ++counted;
      ASSERT_LT((cr[0] * n[0] + cr[1] * n[1] + cr[2] * n[2]) / len, 0.0) << describe(c) << " triangle " << k / 3;
    }
    EXPECT_GT(counted, 0) << describe(c);
  }
}

TEST(GodotPrimitives, ReadsTscnValuesAndAppliesGodotsSetterRules) {
  auto extent = [](const MeshTriangles& m, int axis) {
    float lo = 1e30f, hi = -1e30f;
    for (size_t i = axis; i < m.positions.size(); i += 3)
      lo = std::min(lo, m.positions[i]), hi = std::max(hi, m.positions[i]);
    return std::pair<float, float>(lo, hi);
  };
  const MeshTriangles slab = godot_primitive_mesh("BoxMesh", with_uv2({{"size", "Vector3(4, 0.2, 4)"}}), "t.tscn");
  EXPECT_FLOAT_EQ(extent(slab, 0).second, 2.0f);
  EXPECT_FLOAT_EQ(extent(slab, 1).first, -0.1f);
  EXPECT_FLOAT_EQ(extent(slab, 2).second, 2.0f);
  // Godot sets radius before height: radius 2 raises the default height 2 to 4, then height 3
  // lowers the radius to 1.5.
  const MeshTriangles cap =
      godot_primitive_mesh("CapsuleMesh", with_uv2({{"radius", "2"}, {"height", "3.0"}}), "t.tscn");
  EXPECT_NEAR(extent(cap, 0).second, 1.5f, 1e-6);
  EXPECT_NEAR(extent(cap, 1).second, 1.5f, 1e-6);
  EXPECT_NEAR(extent(cap, 1).first, -1.5f, 1e-6);
  // QuadMesh defaults: 1 x 1 facing +Z.
  const MeshTriangles quad = godot_primitive_mesh("QuadMesh", with_uv2({}), "t.tscn");
  EXPECT_FLOAT_EQ(extent(quad, 0).second, 0.5f);
  EXPECT_FLOAT_EQ(extent(quad, 2).second, 0.0f);
  EXPECT_FLOAT_EQ(quad.normals[2], 1.0f);
  // flip_faces negates the normals.
  const MeshTriangles flipped = godot_primitive_mesh("QuadMesh", with_uv2({{"flip_faces", "true"}}), "t.tscn");
  EXPECT_FLOAT_EQ(flipped.normals[2], -1.0f);
  // Hints: BoxMesh 1 m: (2 / 0.2 + 2 x 2 padding, 3 / 0.2 + 3 x 2); PlaneMesh 2 m: 2 / 0.2 + 2.
  EXPECT_EQ(godot_primitive_lightmap_size_hint("BoxMesh", with_uv2({}), "t.tscn"), (std::array<int, 2>{14, 21}));
  EXPECT_EQ(godot_primitive_lightmap_size_hint("PlaneMesh", with_uv2({}), "t.tscn"), (std::array<int, 2>{12, 12}));
  EXPECT_EQ(godot_primitive_lightmap_size_hint("BoxMesh", with_uv2({{"uv2_padding", "0"}}), "t.tscn"),
            (std::array<int, 2>{10, 15}));
  // A texel size of 0.1 doubles the texels (and halves the padding's share of the chart).
  EXPECT_EQ(godot_primitive_lightmap_size_hint("BoxMesh", with_uv2({}), "t.tscn", 0.1f), (std::array<int, 2>{24, 36}));
  // TorusMesh's radius setters leave the hint alone (Godot 4.6): that of radii 0.5 and 1.
  EXPECT_EQ(godot_primitive_lightmap_size_hint("TorusMesh", with_uv2({{"outer_radius", "3.0"}}), "t.tscn"),
            godot_primitive_lightmap_size_hint("TorusMesh", with_uv2({}), "t.tscn"));
  // PlaneMesh has no UV2 layout of its own: Godot scales UV by 1 - padding / hint.
  const MeshTriangles plane = godot_primitive_mesh("PlaneMesh", with_uv2({}), "t.tscn");
  EXPECT_NEAR(plane.uv[0], 1.0 - 2.0 / 12.0, 1e-7);          // vertex 0: uv (1, 1)
  EXPECT_NEAR(plane.uv[1], 1.0 - (1.0 - 2.0 / 12.0), 1e-7);  // v up
  // Spelling: exponents, signs, spaces.
  const MeshTriangles spelled =
      godot_primitive_mesh("BoxMesh", with_uv2({{"size", "Vector3( 4e0 ,+0.2, 4 )"}}), "t.tscn");
  EXPECT_EQ(spelled.positions, slab.positions);
}

TEST(GodotPrimitives, BoxFrontChartUsesTheWidthSubdivisionsAsGodotDoes) {
  // Godot 4.6 divides the front/back rows' UV2 v by subdivide_width + 1 (not subdivide_height + 1):
  // with 2 height and 0 width subdivisions the front face's chart runs to 3 x its height.
  const MeshTriangles m = godot_primitive_mesh("BoxMesh", with_uv2({{"subdivide_height", "2"}}), "t.tscn");
  const float height_v = 1.0f / (3.0f + 3.0f * 0.4f);  // size.y / (y + y + max(x, z) + 3 x padding)
  float lowest = 1;                                    // v up: the front face's chart grows downwards
  for (size_t i = 0; i < (2 + 2) * 2 * 2; i += 2) lowest = std::min(lowest, m.uv[2 * i + 1]);
  EXPECT_NEAR(1.0f - lowest, 3 * height_v, 1e-6);
  // ... and so lands on the back face's chart (the overlap check sees it).
  EXPECT_GT(uv_coverage(m).overlaps, 0);
}

TEST(GodotPrimitives, RejectsBadInput) {
  auto message = [](const std::string& type, const Props& p) -> std::string {
    try {
      godot_primitive_mesh(type, p, "scene.tscn");
    } catch (const ahd::Error& e) {
      return e.what();
    }
    return "";
  };
  const std::string no_uv2 = message("SphereMesh", {});
  EXPECT_NE(no_uv2.find("scene.tscn: SphereMesh"), std::string::npos) << no_uv2;
  EXPECT_NE(no_uv2.find("add_uv2"), std::string::npos) << no_uv2;
  EXPECT_NE(message("BoxMesh", {{"add_uv2", "false"}}).find("add_uv2"), std::string::npos);
  EXPECT_NE(message("BoxMesh", with_uv2({{"size", "Vector3(4, x, 4)"}})).find("size"), std::string::npos);
  EXPECT_NE(message("BoxMesh", with_uv2({{"size", "Vector3(4, 4)"}})).find("size"), std::string::npos);
  EXPECT_NE(message("BoxMesh", with_uv2({{"size", "Vector3(4, inf, 4)"}})).find("size"), std::string::npos);
  EXPECT_NE(message("BoxMesh", with_uv2({{"size", "Vector3(4, 1e39, 4)"}})).find("size"), std::string::npos);
  EXPECT_NE(message("SphereMesh", with_uv2({{"radius", "nan"}})).find("radius"), std::string::npos);
  EXPECT_NE(message("SphereMesh", with_uv2({{"rings", "3.5"}})).find("rings"), std::string::npos);
  EXPECT_NE(message("SphereMesh", with_uv2({{"rings", "99999999999"}})).find("rings"), std::string::npos);
  EXPECT_NE(message("SphereMesh", with_uv2({{"is_hemisphere", "yes"}})).find("is_hemisphere"), std::string::npos);
  EXPECT_NE(message("PlaneMesh", with_uv2({{"orientation", "3"}})).find("orientation"), std::string::npos);
  EXPECT_NE(message("TorusMesh", with_uv2({{"inner_radius", "1.0"}})).find("inner_radius"), std::string::npos);
  EXPECT_NE(message("SphereMesh", with_uv2({{"radius", "0"}})).find("not finite"), std::string::npos);
  EXPECT_NE(message("TubeTrailMesh", with_uv2({})).find("TubeTrailMesh"), std::string::npos);
  // Vertex bound (2^22): 2047 x 2046 sphere segments is exactly the most; one more ring is over.
  const std::string big = message("SphereMesh", with_uv2({{"radial_segments", "2047"}, {"rings", "2047"}}));
  EXPECT_NE(big.find("vertices"), std::string::npos) << big;
  EXPECT_NE(
      message("BoxMesh", with_uv2({{"subdivide_width", "100000"}, {"subdivide_height", "100000"}})).find("vertices"),
      std::string::npos);
  EXPECT_TRUE(ahd::is_godot_primitive_mesh("CapsuleMesh"));
  EXPECT_TRUE(ahd::is_godot_primitive_mesh("QuadMesh"));
  EXPECT_FALSE(ahd::is_godot_primitive_mesh("ArrayMesh"));
  EXPECT_FALSE(ahd::is_godot_primitive_mesh("RibbonTrailMesh"));
  // Unused properties are ignored, whatever their text.
  EXPECT_EQ(message("BoxMesh", with_uv2({{"material", "SubResource(\"M_1\")"}, {"custom_aabb", "AABB(0"}})), "");
}

// ---- the fixture written by Godot 4.6 ------------------------------------------------------------

// A JSON property value as the .tscn text Godot writes for it.
std::string tscn_text(const nlohmann::json& v) {
  char buf[64];
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  if (v.is_number_integer()) return std::to_string(v.get<long long>());
  if (v.is_number()) {
    std::snprintf(buf, sizeof buf, "%.17g", v.get<double>());
    return buf;
  }
  if (v.is_array() && (v.size() == 2 || v.size() == 3)) {
    std::string s = v.size() == 3 ? "Vector3(" : "Vector2(";
    for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + tscn_text(v[i]);
    return s + ")";
  }
  return v.is_string() ? v.get<std::string>() : v.dump();
}

// Our mesh of `type`/`props` against one fixture entry (Godot's arrays): hint exact, positions,
// normals and UV2 within 1e-6 (the fixture's numbers are Godot's float32 values), indices exact.
void expect_matches_godot(const nlohmann::json& entry, const std::string& type, const Props& props,
                          const std::string& what) {
  if (entry.contains("lightmap_size_hint")) {
    const auto hint = godot_primitive_lightmap_size_hint(type, props, "fixture");
    EXPECT_EQ(hint[0], entry["lightmap_size_hint"][0].get<int>()) << what;
    EXPECT_EQ(hint[1], entry["lightmap_size_hint"][1].get<int>()) << what;
  }
  const MeshTriangles m = godot_primitive_mesh(type, props, "fixture");
  ASSERT_EQ(entry.at("surfaces").size(), 1u) << what;
  const nlohmann::json& s = entry["surfaces"][0];
  const std::vector<double> vertex = s.at("vertex"), normal = s.at("normal"), uv2 = s.at("uv2");
  const std::vector<long long> index = s.at("index");
  ASSERT_EQ(m.positions.size(), vertex.size()) << what;
  ASSERT_EQ(m.normals.size(), normal.size()) << what;
  ASSERT_EQ(m.uv.size(), uv2.size()) << what;
  ASSERT_EQ(m.indices.size(), index.size()) << what;
  double worst_p = 0, worst_n = 0, worst_t = 0;
  for (size_t i = 0; i < vertex.size(); ++i) worst_p = std::max(worst_p, std::fabs(m.positions[i] - vertex[i]));
  for (size_t i = 0; i < normal.size(); ++i) worst_n = std::max(worst_n, std::fabs(m.normals[i] - normal[i]));
  for (size_t i = 0; i < uv2.size(); ++i) {
    const double ours = i % 2 ? 1.0 - m.uv[i] : m.uv[i];  // the fixture is Godot's v-down
    worst_t = std::max(worst_t, std::fabs(ours - uv2[i]));
  }
  EXPECT_LE(worst_p, 1e-6) << what;
  EXPECT_LE(worst_n, 1e-6) << what;
  EXPECT_LE(worst_t, 1e-6) << what;
  size_t index_mismatches = 0;
  for (size_t i = 0; i < index.size(); ++i) index_mismatches += (long long)m.indices[i] != index[i];
  EXPECT_EQ(index_mismatches, 0u) << what;
}

nlohmann::json read_fixture(const std::filesystem::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

TEST(GodotPrimitives, MatchesGodot46Fixture) {
  const auto path = ahd_test::test_data("godot/generated/primitives.json");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path.string() << " missing (written by Godot 4.6)";
  const nlohmann::json fixture = read_fixture(path);
  ASSERT_TRUE(fixture.is_array());
  int compared = 0;
  for (const nlohmann::json& entry : fixture) {
    const std::string type = entry.at("type");
    Props props;
    for (const auto& [k, v] : entry.at("props").items()) props[k] = tscn_text(v);
    const std::string what = type + " " + entry.at("props").dump();
    if (!ahd::is_godot_primitive_mesh(type)) continue;  // e.g. trail meshes, not lightmapped
    if (props.count("add_uv2") == 0 || props["add_uv2"] != "true") {
      EXPECT_THROW(godot_primitive_mesh(type, props, "fixture"), ahd::Error) << what;
      continue;
    }
    expect_matches_godot(entry, type, props, what);
    ++compared;
  }
  EXPECT_GT(compared, 0);
}

// The same meshes read from the text Godot itself saved (primitives.tscn: only the properties that
// differ from the defaults, in Godot's order and spelling, e.g. "2.0", "Vector3(0.5, 0, -1)").
TEST(GodotPrimitives, GodotsOwnTscnTextGivesGodotsArrays) {
  const auto json_path = ahd_test::test_data("godot/generated/primitives.json");
  const auto tscn_path = ahd_test::test_data("godot/generated/primitives.tscn");
  if (!std::filesystem::exists(json_path) || !std::filesystem::exists(tscn_path))
    GTEST_SKIP() << tscn_path.string() << " or primitives.json missing (written by Godot 4.6)";
  // [sub_resource type="T" id="I"] followed by `key = value` lines, up to the next section.
  std::map<std::string, std::pair<std::string, Props>> resources;
  std::ifstream in(tscn_path);
  std::string line, current;
  auto attr = [](const std::string& l, const std::string& key) {
    const size_t at = l.find(key + "=\"");
    if (at == std::string::npos) return std::string();
    const size_t b = at + key.size() + 2;
    return l.substr(b, l.find('"', b) - b);
  };
  while (std::getline(in, line)) {
    if (line.rfind("[", 0) == 0) {
      current = line.rfind("[sub_resource ", 0) == 0 ? attr(line, "id") : "";
      if (!current.empty()) resources[current].first = attr(line, "type");
      continue;
    }
    const size_t eq = line.find(" = ");
    if (!current.empty() && eq != std::string::npos)
      resources[current].second[line.substr(0, eq)] = line.substr(eq + 3);
  }
  int compared = 0;
  for (const nlohmann::json& entry : read_fixture(json_path)) {
    if (!entry.contains("node") || !resources.count(entry["node"].get<std::string>())) continue;
    const auto& [type, props] = resources[entry["node"].get<std::string>()];
    if (!ahd::is_godot_primitive_mesh(type) || !props.count("add_uv2")) continue;
    ASSERT_EQ(type, entry.at("type").get<std::string>());
    expect_matches_godot(entry, type, props, "primitives.tscn " + entry["node"].get<std::string>());
    ++compared;
  }
  EXPECT_GT(compared, 0);
}

}  // namespace
