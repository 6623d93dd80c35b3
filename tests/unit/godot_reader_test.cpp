// The Godot project reader on projects as they are in the wild: every binary resource format a
// Godot 3.x–4.x editor writes (3..6), the 4.0 pre-release and Godot 3 text spellings, meshes
// defined inside a scene, the scene found anywhere in its project, and each mesh's own entry of
// the importer's unwrap cache (Godot's key, not the vertex count). The binary and text files are
// made here from the format facts (core/io/resource_format_binary.cpp,
// scene/resources/resource_format_text.cpp); the real project is tests/data/bakes/godot42-vermilion.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "fixture_writers.h"
#include "bakers/godot/godot_fbx.h"
#include "bakers/godot/godot_unwrap_key.h"
#include "cli_runner.h"
#include "file_bytes.h"
#include "core/error.h"
#include "bakers/godot/godot_lmbake.h"
#include "bakers/godot/godot_scene.h"
#include "bakers/godot/godot_tscn.h"
#include "bakers/godot/godot_unwrap_cache.h"
#include "test_data.h"
#include "godot_reader_fixture.h"

namespace fs = std::filesystem;
using namespace ahd;
using namespace ahd_fixture::godot_reader_fixture;

// Gap 1: format 6 (every Godot >= 4.3 bake) and 4 are read like 3 and 5; the new tag is parsed.
TEST(GodotReader, LmbakeFormatsThreeToSixAreRead) {
  for (uint32_t format : {3u, 4u, 5u, 6u}) {
    const std::vector<uint8_t> b = lmbake_bytes(format);
    const GodotLightmapData d = parse_godot_lmbake(b.data(), b.size(), "w.lmbake");
    EXPECT_EQ(d.format, int(format));
    EXPECT_TRUE(d.uses_spherical_harmonics) << format;
    ASSERT_EQ(d.users.size(), 1u) << format;
    EXPECT_EQ(d.users[0].path, "../Box");
    EXPECT_EQ(d.users[0].rect[0], 0.25);
    EXPECT_EQ(d.users[0].rect[3], 0.25);
    EXPECT_EQ(d.users[0].slice, 1);
  }
  // The uid field is in the header whether or not the flags say the uid is used.
  const std::vector<uint8_t> no_uid = lmbake_bytes(6, false);
  EXPECT_EQ(parse_godot_lmbake(no_uid.data(), no_uid.size(), "w").users.size(), 1u);
  // A format Godot has not written yet, and a compressed resource: one line naming the file.
  std::vector<uint8_t> seven = lmbake_bytes(7);
  try {
    parse_godot_lmbake(seven.data(), seven.size(), "w.lmbake");
    ADD_FAILURE() << "format 7 accepted";
  } catch (const Error& e) {
    EXPECT_TRUE(contains(e.what(), "w.lmbake: Godot resource format 7")) << e.what();
    EXPECT_TRUE(contains(e.what(), "3..6")) << e.what();
  }
  std::vector<uint8_t> rscc = seven;
  std::memcpy(rscc.data(), "RSCC", 4);
  try {
    parse_godot_lmbake(rscc.data(), rscc.size(), "c.lmbake");
    ADD_FAILURE() << "RSCC accepted";
  } catch (const Error& e) {
    EXPECT_TRUE(contains(e.what(), "c.lmbake: a compressed Godot resource (RSCC)")) << e.what();
  }
  // Truncations never read past the end.
  const std::vector<uint8_t> six = lmbake_bytes(6);
  for (size_t n = 0; n < six.size(); n += 7) EXPECT_THROW(parse_godot_lmbake(six.data(), n, "t"), Error) << n;
}

// Gap 2: Godot 3 (format=2) and the 4.0 pre-releases: spaces in ExtResource( … ) and
// Transform3D( … ), bare integer ids, `Transform(` — all read as the 4.x spelling.
TEST(GodotReader, OlderTextSpellingsAreRead) {
  const GodotTscn g3 = parse_godot_tscn(
      "[gd_scene load_steps=3 format=2]\n\n"
      "[ext_resource path=\"res://chair.glb\" type=\"PackedScene\" id=1]\n"
      "[ext_resource path=\"res://world.lmbake\" type=\"LightmapGIData\" id=2]\n\n"
      "[node name=\"World\" type=\"Spatial\"]\n\n"
      "[node name=\"Chair\" parent=\".\" instance=ExtResource( 1 )]\n"
      "transform = Transform( 1, 0, 0, 0, 1, 0, 0, 0, 1, 4, 5, 6 )\n\n"
      "[node name=\"LightmapGI\" type=\"LightmapGI\" parent=\".\"]\nlight_data = ExtResource( 2 )\n",
      "old.tscn");
  EXPECT_EQ(g3.format, 2);
  ASSERT_EQ(g3.nodes.size(), 3u);
  EXPECT_EQ(g3.nodes[1].instance, "1");
  ASSERT_NE(g3.find_ext("1"), nullptr);
  EXPECT_EQ(g3.find_ext("1")->path, "res://chair.glb");
  EXPECT_TRUE(g3.nodes[1].has_transform);
  EXPECT_EQ(g3.nodes[1].transform[9], 4);
  EXPECT_EQ(g3.nodes[1].transform[11], 6);
  EXPECT_EQ(g3.nodes[2].light_data, "2");

  const GodotTscn pre = parse_godot_tscn(
      "[gd_scene load_steps=2 format=3]\n"
      "[ext_resource type=\"PackedScene\" path=\"res://chair.glb\" id=\"1_ab\"]\n"
      "[node name=\"World\" type=\"Node3D\"]\n"
      "[node name=\"Chair\" parent=\".\" instance=ExtResource( \"1_ab\" )]\n"
      "transform = Transform3D( 0, 0, 1, 0, 1, 0, -1, 0, 0, 7.5, 0, -2 )\n",
      "pre.tscn");
  EXPECT_EQ(pre.nodes[1].instance, "1_ab");
  EXPECT_EQ(pre.nodes[1].transform[6], -1);
  EXPECT_EQ(pre.nodes[1].transform[9], 7.5);
  EXPECT_EQ(godot_resource_ref("SubResource(  \"Box_1\"  )", "SubResource"), "Box_1");
  EXPECT_EQ(godot_resource_ref("ExtResource(\"a\") extra", "ExtResource"), "");
  EXPECT_EQ(godot_resource_ref("SubResource(\"a\")", "ExtResource"), "");
  try {
    parse_godot_tscn("[node name=\"A\"]\n[node name=\"B\" parent=\".\" instance=Chair]\n", "bad.tscn");
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_TRUE(contains(e.what(), "bad.tscn: line 2: instance is not ExtResource(\"id\") but 'Chair'")) << e.what();
  }
}

// Gap 5: sub_resource sections are kept (type, id, raw property text, multi-line values whole) and
// `mesh = SubResource(…)` / `mesh = ExtResource(…)` is recorded on the node.
TEST(GodotReader, SubResourcesAndNodeMeshesAreKept) {
  const std::string surfaces =
      "[{\n\"aabb\": AABB(-1, -1, -1, 2, 2, 2),\n\"format\": 34359742487,\n\"name\": \"a [b\",\n"
      "\"vertex_data\": PackedByteArray(0, 1, 2)\n}]";
  const GodotTscn t = parse_godot_tscn(
      "[gd_scene load_steps=4 format=3]\n"
      "[ext_resource type=\"ArrayMesh\" path=\"res://rock.tres\" id=\"2_r\"]\n"
      "[sub_resource type=\"ArrayMesh\" id=\"ArrayMesh_x1\"]\n_surfaces = " +
          surfaces +
          "\nblend_shape_mode = 0\n\n"
          "[sub_resource type=\"BoxMesh\" id=\"BoxMesh_q1\"]\nadd_uv2 = true\nsize = Vector3(1, 2, 3)\n\n"
          "[node name=\"World\" type=\"Node3D\"]\n"
          "[node name=\"Rock\" type=\"MeshInstance3D\" parent=\".\"]\nmesh = ExtResource(\"2_r\")\n"
          "[node name=\"Inline\" type=\"MeshInstance3D\" parent=\".\"]\nmesh = SubResource(\"ArrayMesh_x1\")\n"
          "[node name=\"Box\" type=\"MeshInstance3D\" parent=\".\"]\nmesh = SubResource( \"BoxMesh_q1\" )\n",
      "s.tscn");
  ASSERT_EQ(t.sub.size(), 2u);
  const GodotTscnSub* am = t.find_sub("ArrayMesh_x1");
  ASSERT_NE(am, nullptr);
  EXPECT_EQ(am->type, "ArrayMesh");
  EXPECT_EQ(am->props.at("_surfaces"), surfaces);  // whole, line breaks kept
  EXPECT_EQ(am->props.at("blend_shape_mode"), "0");
  EXPECT_EQ(am->line, 3);
  const GodotTscnSub* box = t.find_sub("BoxMesh_q1");
  ASSERT_NE(box, nullptr);
  EXPECT_EQ(box->props.at("size"), "Vector3(1, 2, 3)");
  ASSERT_EQ(t.nodes.size(), 4u);
  EXPECT_EQ(t.nodes[1].mesh_ext, "2_r");
  EXPECT_EQ(t.nodes[2].mesh_sub, "ArrayMesh_x1");
  EXPECT_EQ(t.nodes[3].mesh_sub, "BoxMesh_q1");
  EXPECT_THROW(parse_godot_tscn("[node name=\"A\"]\n[sub_resource type=\"X\" id=\"1\"]\nv = [{\n", "open.tscn"), Error);
}

// Gap 5 + 6: an instance whose mesh is a sub_resource goes to the mesh-resource reader; while that
// reader does not read the kind, the instance is named with the cause, and the paths stay as given.
TEST(GodotReader, SceneMeshesAreRoutedAndNamedWhenNotRead) {
  const fs::path dir = ahd_test::temp_dir("godot_reader_route");
  write(dir / "project.godot", "config_version=5\n\n[rendering]\n\nlightmapping/primitive_meshes/texel_size=0.1\n");
  write(dir / "scenes/world.lmbake", lmbake_bytes(6));
  const std::string box = "[node name=\"Box\" type=\"MeshInstance3D\" parent=\".\"]\nmesh = SubResource(\"BoxMesh_q1\")\n";
  write(dir / "scenes/world.tscn", lightmap_scene("res://scenes/world.lmbake", box));
  const fs::path rel = fs::relative(dir / "scenes/world.tscn");
  ASSERT_TRUE(rel.is_relative());
  // A primitive with add_uv2 is read (godot_primitives.h): one placed instance, 24 box vertices,
  // and project.godot (its texel size shapes the UV2) is among the files the result depends on.
  const GodotSceneMeshes g = load_godot_scene(rel.string());
  ASSERT_EQ(g.scene.instances.size(), 1u);
  EXPECT_EQ(g.scene.instances[0].vertices, 24u);
  EXPECT_NE(std::find(g.files.begin(), g.files.end(), (rel.parent_path().parent_path() / "project.godot").string()),
            g.files.end());
  // A mesh type without lightmap UV2 (TextMesh) is left out, named with its cause; with no other
  // user the .lmbake is refused, relative paths staying relative.
  std::string text = lightmap_scene("res://scenes/world.lmbake", box);
  text.replace(text.find("type=\"BoxMesh\""), 15, "type=\"TextMesh\"");
  write(dir / "scenes/world.tscn", text);
  try {
    load_godot_scene(rel.string());
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind((rel.parent_path() / "world.lmbake").string() + ": none of its 1 users", 0), 0u) << m;
    EXPECT_TRUE(contains(m, "lightmap user ../Box left out: TextMesh sub_resource \"BoxMesh_q1\": ")) << m;
    EXPECT_TRUE(contains(m, "TextMesh is not a mesh with lightmap UV2 that ahdpack reads")) << m;
    EXPECT_FALSE(contains(m, " " + dir.string()) || m.rfind(dir.string(), 0) == 0) << m;  // relative stays relative
  }
  fs::remove_all(dir);
}

// Gap 3: the scene is found anywhere in the project (the nearest project.godot above the EXR),
// not in .godot/ or other hidden folders; several: the one beside the EXR, else a list and the remedy.
TEST(GodotReader, SceneIsFoundInTheWholeProject) {
  const fs::path dir = ahd_test::temp_dir("godot_reader_find");
  write(dir / "project.godot", "config_version=5\n");
  write(dir / "bakes/world.exr", "not read here");
  write(dir / "bakes/world.lmbake", lmbake_bytes(5));
  const std::string scene = lightmap_scene("res://bakes/world.lmbake", "");
  write(dir / "levels/one/world_level.tscn", scene);
  write(dir / ".godot/imported/copy.tscn", scene);                                       // hidden: skipped
  write(dir / "levels/other.tscn", lightmap_scene("res://elsewhere/world.lmbake", ""));  // another bake
  const fs::path rel = fs::relative(dir / "bakes/world.exr");
  EXPECT_EQ(find_godot_scene(rel.string()), (rel.parent_path().parent_path() / "levels/one/world_level.tscn").string());
  EXPECT_EQ(find_godot_scene((dir / "bakes/world.exr").string()), (dir / "levels/one/world_level.tscn").string());
  // A second scene baking the same file: refused with both names and --godot-scene.
  write(dir / "levels/two/again.tscn", scene);
  try {
    find_godot_scene((dir / "bakes/world.exr").string());
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_TRUE(contains(m, "2 scenes bake it")) << m;
    EXPECT_TRUE(contains(m, "world_level.tscn")) << m;
    EXPECT_TRUE(contains(m, "again.tscn")) << m;
    EXPECT_TRUE(contains(m, "--godot-scene")) << m;
  }
  // …unless one lies beside the EXR.
  write(dir / "bakes/world.tscn", scene);
  EXPECT_EQ(find_godot_scene((dir / "bakes/world.exr").string()), (dir / "bakes/world.tscn").string());
  // No .lmbake beside the EXR: nothing to look for.
  EXPECT_EQ(find_godot_scene((dir / "levels/none.exr").string()), "");
  fs::remove_all(dir);
}

TEST(GodotReader, Md5MatchesRfc1321) {
  const auto hex = [](const std::string& s) { return godot_unwrap_key_hex(md5_digest(s.data(), s.size())); };
  EXPECT_EQ(hex(""), "d41d8cd98f00b204e9800998ecf8427e");
  EXPECT_EQ(hex("abc"), "900150983cd24fb0d6963f7d28e17f72");
  EXPECT_EQ(hex("message digest"), "f96b697d7cb7938d525a2f31aaf161d0");
  EXPECT_EQ(hex("12345678901234567890123456789012345678901234567890123456789012345678901234567890"),
            "57edf4a22be3c955ac49da2e2107b67a");
}

// Gap 4: each mesh takes the entry whose hash is its Godot key. On the real project every cached
// mesh finds its entry by key (none by its triangles); a cache entry moved to another file is
// not taken by a mesh of that file, and the instance is named with the reason.
TEST(GodotReader, UnwrapCacheEntriesAreMatchedByGodotsKey) {
  const fs::path bake = ahd_test::test_data("bakes/godot42-vermilion/project");
  if (!fs::exists(bake / "scenes/world.tscn")) GTEST_SKIP() << "no " << bake / "scenes/world.tscn";
  const GodotSceneMeshes g = load_godot_scene((bake / "scenes/world.tscn").string());
  EXPECT_EQ(g.scene.instances.size(), 55u);
  for (const std::string& n : g.notes) EXPECT_FALSE(contains(n, "by its triangles")) << n;

  const fs::path dir = ahd_test::temp_dir("godot_reader_key");
  fs::copy(bake, dir / "project", fs::copy_options::recursive);
  const fs::path models = dir / "project/assets/models";
  // The window's cache now holds the doorframe's entry: no entry of the window's key is there.
  fs::copy_file(models / "apartments/doorframe/doorframe.glb.unwrap_cache",
                models / "apartments/window/window.glb.unwrap_cache", fs::copy_options::overwrite_existing);
  const GodotSceneMeshes w = load_godot_scene((dir / "project/scenes/world.tscn").string());
  EXPECT_LT(w.scene.instances.size(), 55u);
  bool named = false;
  for (const std::string& n : w.notes)
    named = named || (contains(n, "lightmap user ../ApartmentA1Props/Windows/Window/Window left out: ") &&
                      contains(n, "window.glb.unwrap_cache has no entry for mesh 'Plane.012' (145 vertices)"));
  EXPECT_TRUE(named) << testing::PrintToString(w.notes);
  // The chair's entry with its hash damaged: found by its triangles (said so), nothing else changes.
  const fs::path chair = models / "chair/chair.glb.unwrap_cache";
  std::vector<uint8_t> c;
  {
    std::ifstream f(chair, std::ios::binary);
    c.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
  }
  ASSERT_GT(c.size(), 20u);
  c[4] ^= 0xff;
  write(chair, c);
  const GodotSceneMeshes h = load_godot_scene((dir / "project/scenes/world.tscn").string());
  bool by_triangles = false;
  for (const std::string& n : h.notes)
    by_triangles = by_triangles || contains(n, "chair.glb.unwrap_cache: mesh 'Cylinder.006'");
  EXPECT_TRUE(by_triangles) << testing::PrintToString(h.notes);
  EXPECT_EQ(h.scene.instances.size(), w.scene.instances.size());
  fs::remove_all(dir);
}

// The bed frame of the real project sits under a rotated (90 degrees about y) and scaled glTF node:
// its key needs the node's scale exactly as Godot's float basis gives it. Its entry is found by key.
TEST(GodotReader, RotatedScaledNodeFindsItsEntryByKey) {
  const fs::path models = ahd_test::test_data("bakes/godot42-vermilion/project/assets/models/bed");
  if (!fs::exists(models / "bedframe.glb")) GTEST_SKIP() << "no " << models / "bedframe.glb";
  const fs::path dir = ahd_test::temp_dir("godot_reader_bed");
  write(dir / "project.godot", "config_version=5\n");
  fs::create_directories(dir / "bed");
  for (const char* f : {"bedframe.glb", "bedframe.glb.import", "bedframe.glb.unwrap_cache"})
    fs::copy_file(models / f, dir / "bed" / f);
  write(dir / "world.lmbake", lmbake_bytes(5, true, {{"..", "Bed", "Cube_002"}}));
  write(dir / "world.tscn", lit_scene("PackedScene", "bed/bedframe.glb", "Bed"));
  const GodotSceneMeshes g = load_godot_scene((dir / "world.tscn").string());
  ASSERT_EQ(g.scene.instances.size(), 1u) << testing::PrintToString(g.notes);
  for (const std::string& n : g.notes) EXPECT_FALSE(contains(n, "by its triangles")) << n;
  fs::remove_all(dir);
}

// The regression: two meshes of one file with the same vertex count (two quads, the second twice
// as wide) and the cache holding the second's entry first. Matched by vertex count the first quad
// took the second's UV2; by Godot's key each takes its own.
TEST(GodotReader, MeshesOfEqualVertexCountTakeTheirOwnEntries) {
  const fs::path dir = ahd_test::temp_dir("godot_reader_twins");
  write(dir / "project.godot", "config_version=5\n");
  const float pos[2][12] = {{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, {0, 0, 0, 2, 0, 0, 2, 1, 0, 0, 1, 0}};
  const float nrm[12] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  const uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
  std::vector<uint8_t> bin;
  const auto put = [&](const void* p, size_t n) {
    bin.insert(bin.end(), static_cast<const uint8_t*>(p), static_cast<const uint8_t*>(p) + n);
  };
  put(pos[0], 48), put(pos[1], 48), put(nrm, 48), put(idx, 24);
  write(dir / "m/twins.bin", bin);
  std::string views, accessors;
  const size_t off[4] = {0, 48, 96, 144}, len[4] = {48, 48, 48, 24};
  for (int v = 0; v < 4; ++v)
    views += std::string(v ? "," : "") + "{\"buffer\":0,\"byteOffset\":" + std::to_string(off[v]) +
             ",\"byteLength\":" + std::to_string(len[v]) + "}";
  accessors =
      "{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[1,1,0]},"
      "{\"bufferView\":1,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[2,1,0]},"
      "{\"bufferView\":2,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\"},"
      "{\"bufferView\":3,\"componentType\":5125,\"count\":6,\"type\":\"SCALAR\"}";
  write(
      dir / "m/twins.gltf",
      "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
      "\"nodes\":[{\"name\":\"Top\",\"children\":[1,2]},{\"name\":\"A\",\"mesh\":0},{\"name\":\"B\",\"mesh\":1}],"
      "\"meshes\":[{\"name\":\"QuadA\",\"primitives\":[{\"attributes\":{\"POSITION\":0,\"NORMAL\":2},\"indices\":3}]},"
      "{\"name\":\"QuadB\",\"primitives\":[{\"attributes\":{\"POSITION\":1,\"NORMAL\":2},\"indices\":3}]}],"
      "\"buffers\":[{\"uri\":\"twins.bin\",\"byteLength\":168}],\"bufferViews\":[" +
          views + "],\"accessors\":[" + accessors + "]}");
  write(dir / "m/twins.gltf.import", "[params]\n\nmeshes/light_baking=2\nmeshes/lightmap_texel_size=0.2\n");
  // The cache: B's entry (UV2 in the right half), then A's (left half); Godot's winding a, c, b.
  const std::vector<uint32_t> winding = {0, 2, 1, 0, 3, 2};
  const float one[3] = {1, 1, 1};
  Rsrc c;
  c.u32(2);
  for (int m : {1, 0}) {
    const std::vector<float> p(pos[m], pos[m] + 12), n(nrm, nrm + 12);
    float uv2[8];
    for (uint32_t v = 0; v < 4; ++v)
      uv2[v * 2] = 0.5f * float(m) + 0.5f * pos[m][v * 3] / float(m + 1), uv2[v * 2 + 1] = pos[m][v * 3 + 1];
    unwrap_entry(c, godot_unwrap_key(p, n, winding, one, 0.2f), 8, 8, uv2, winding);
  }
  write(dir / "m/twins.gltf.unwrap_cache", c.b);
  write(dir / "world.lmbake", lmbake_bytes(5, true, {{"..", "Twins", "Top", "A"}, {"..", "Twins", "Top", "B"}}));
  write(dir / "world.tscn", lit_scene("PackedScene", "m/twins.gltf", "Twins"));
  const GodotSceneMeshes g = load_godot_scene((dir / "world.tscn").string());
  ASSERT_EQ(g.scene.instances.size(), 2u) << testing::PrintToString(g.notes);
  for (const std::string& n : g.notes) EXPECT_FALSE(contains(n, "by its triangles")) << n;
  // Instance 0 is A: its UV2 (v up: u as written) lies in the left half; B's in the right half.
  for (size_t k = 0; k < 2; ++k) {
    const MeshInstance& inst = g.scene.instances[k];
    EXPECT_TRUE(contains(inst.node, k == 0 ? "/A" : "/B")) << inst.node;
    for (size_t v = inst.first_vertex; v < inst.first_vertex + inst.vertices; ++v) {
      const float u = g.scene.mesh.uv[v * 2];
      EXPECT_TRUE(k == 0 ? u <= 0.5f : u >= 0.5f) << inst.node << " u " << u;
    }
  }
  fs::remove_all(dir);
}


// An FBX instance (Godot >= 4.3 imports .fbx through ufbx) is read through Assimp and rebuilt as
// Godot's importer builds it, so that its mesh finds its unwrap-cache entry by Godot's key: the
// instance is placed, at its node's transform, with the entry's UV2.
TEST(GodotFbx, InstanceTakesItsUv2FromTheUnwrapCacheByKey) {
  AHD_REQUIRE_DATA(ahd_test::test_data("godot/handmade/room.fbx"));
  const fs::path dir = fbx_project("godot_fbx_key", room_cache(false));
  const GodotSceneMeshes g = load_godot_scene((dir / "world.tscn").string());
  ASSERT_EQ(g.scene.instances.size(), 1u) << testing::PrintToString(g.notes);
  EXPECT_TRUE(g.unplaced.empty());
  for (const std::string& n : g.notes) EXPECT_FALSE(contains(n, "by its triangles")) << n;
  EXPECT_EQ(g.scene.instances[0].node, "../Room/Floor");
  ASSERT_EQ(g.scene.mesh.positions.size(), 12u);
  ASSERT_EQ(g.scene.mesh.uv.size(), 8u);
  // World positions: the Godot vertex order, scaled by 2 and moved by (1, 0, 2); UV2 v up.
  const float world[12] = {5, 0, 0, 5, 0, 2, 1, 0, 2, 1, 0, 0};
  for (int k = 0; k < 12; ++k) EXPECT_FLOAT_EQ(g.scene.mesh.positions[size_t(k)], world[k]) << k;
  for (int v = 0; v < 4; ++v) {
    EXPECT_FLOAT_EQ(g.scene.mesh.uv[size_t(v * 2)], kFbxUv2[v * 2]) << v;
    EXPECT_FLOAT_EQ(g.scene.mesh.uv[size_t(v * 2 + 1)], 1.0f - kFbxUv2[v * 2 + 1]) << v;
  }
  for (int v = 0; v < 4; ++v) EXPECT_FLOAT_EQ(g.scene.mesh.normals[size_t(v * 3 + 1)], 1.0f) << v;
  EXPECT_NE(std::find(g.files.begin(), g.files.end(), (dir / "m/room.fbx.unwrap_cache").string()), g.files.end());
  fs::remove_all(dir);

  // The same entry under another key: not Godot's key for this mesh, found by its triangles (said so).
  const fs::path d2 = fbx_project("godot_fbx_damaged", room_cache(true));
  const GodotSceneMeshes h = load_godot_scene((d2 / "world.tscn").string());
  ASSERT_EQ(h.scene.instances.size(), 1u);
  bool by_triangles = false;
  for (const std::string& n : h.notes)
    by_triangles = by_triangles || contains(n, "mesh 'FloorMesh' (4 vertices) takes entry 1");
  EXPECT_TRUE(by_triangles) << testing::PrintToString(h.notes);
  fs::remove_all(d2);

  // Imported through FBX2glTF: not reproduced, the user is named with the reason.
  const fs::path d3 = fbx_project("godot_fbx_fbx2gltf", room_cache(false), "fbx/importer=1\n");
  try {
    load_godot_scene((d3 / "world.tscn").string());
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_TRUE(contains(e.what(), "FBX2glTF")) << e.what();
  }
  fs::remove_all(d3);
}

// The arrays Godot 4.6's own FBX importer builds (its FBXDocument, run in the official web build by
// tests/tools/godot/gen/fbx: node transforms, vertices and indices as surface_get_arrays gives
// them), from tests/data/godot/handmade/room_zup.fbx (Z up, centimetres, a non-planar quad, the
// node rotated 90 degrees about z and scaled by 2) and quads.fbx (quads whose shorter diagonal is
// 0-2, 1-3, or neither): the geometry is scaled to metres but not rotated, the axis conversion is
// the root node's transform, and a quad is split along its shorter diagonal (0-2 on a tie).
TEST(GodotFbx, ArraysAreThoseGodot46Builds) {
  AHD_REQUIRE_DATA(ahd_test::test_data("godot/handmade/quads.fbx"));
  const GodotFbxScene z = read_godot_fbx(ahd_test::test_data("godot/handmade/room_zup.fbx").string());
  ASSERT_EQ(z.nodes.size(), 1u);
  ASSERT_EQ(z.meshes.size(), 1u);
  EXPECT_EQ(z.nodes[0].name, "Floor");
  // Godot: basis columns X (0, 0, -2), Y (-2, 0, 0), Z (0, 2, 0), origin (1, 0.5, 2).
  const float local[16] = {0, -2, 0, 1, 0, 0, 2, 0.5f, -2, 0, 0, 2, 0, 0, 0, 1};
  for (int k = 0; k < 16; ++k) EXPECT_NEAR(z.nodes[0].local[size_t(k)], local[k], 1e-6) << k;
  EXPECT_EQ(z.meshes[0].positions, (std::vector<float>{0, 1, 0, 2, 1, 0.3f, 2, 0, 0, 0, 0, 0}));
  EXPECT_EQ(z.meshes[0].indices, (std::vector<uint32_t>{0, 1, 2, 2, 3, 0}));
  EXPECT_FALSE(z.meshes[0].polygons);

  const GodotFbxScene q = read_godot_fbx(ahd_test::test_data("godot/handmade/quads.fbx").string());
  ASSERT_EQ(q.meshes.size(), 4u);
  const std::vector<std::vector<float>> vertex = {{2, 0, -1, 2, 0, 0, 0, 0, 0, 0, 0, -1},
                                                  {0, 0, -1, 2.2f, 0, -1, 2, 0, 0, 0, 0, 0},
                                                  {1.8f, 0, -1, 2, 0, 0, 0, 0, 0, 0, 0, -1}};
  for (size_t m = 0; m < 3; ++m) {
    EXPECT_EQ(q.meshes[m].positions, vertex[m]) << q.meshes[m].name;
    EXPECT_EQ(q.meshes[m].indices, (std::vector<uint32_t>{0, 1, 2, 2, 3, 0})) << q.meshes[m].name;
  }
  // A pentagon: Godot gives (1,0,-2) (0,0,0) (-0.5,0,-1) (2,0,0) (2.5,0,-1), 0 1 2 0 3 1 0 4 3 (ufbx's
  // split); the reader's fan differs and says so.
  EXPECT_TRUE(q.meshes[3].polygons);
}

// An .obj named as a mesh resource (Godot's "OBJ as Mesh" importer, generate_lightmap_uv2 on) is
// rebuilt as that importer builds it (resource_importer_obj.cpp: positions times scale_mesh, the
// face 1 2 3 4 as the triangles (2, 1, 3), (3, 1, 4), corners merged in order of first use) and takes
// its UV2 from NAME.obj.unwrap_cache by Godot's key (identity transform: unit scale).
TEST(GodotObj, MeshResourceTakesItsUv2FromTheUnwrapCacheByKey) {
  const fs::path dir = ahd_test::temp_dir("godot_obj_key");
  write(dir / "project.godot", "config_version=5\n");
  write(dir / "m/tile.obj",
        "# a quad\no Tile\nv 0 0 0\nv 2 0 0\nv 2 0 -1\nv 0 0 -1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
        "vn 0 1 0\ns off\nf 1/1/1 2/2/1 3/3/1 4/4/1\n");
  const std::string import =
      "[remap]\n\nimporter=\"wavefront_obj\"\ntype=\"Mesh\"\n\n[params]\n\ngenerate_tangents=true\n"
      "scale_mesh=Vector3(2, 2, 2)\noffset_mesh=Vector3(0, 0, 0)\n";
  write(dir / "m/tile.obj.import", import + "generate_lightmap_uv2=true\ngenerate_lightmap_uv2_texel_size=0.2\n");
  // Godot's arrays: corners 2 1 3, 3 1 4 → vertices (4,0,0) (0,0,0) (4,0,-2) (0,0,-2), triangles 0 1 2, 2 1 3.
  const std::vector<float> pos = {4, 0, 0, 0, 0, 0, 4, 0, -2, 0, 0, -2};
  const std::vector<float> nrm = {0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0};
  const std::vector<uint32_t> idx = {0, 1, 2, 2, 1, 3};
  const float one[3] = {1, 1, 1};
  const GodotUnwrapKey key = godot_unwrap_key(pos, nrm, idx, one, 0.2f);
  const float uv2[8] = {0.8f, 0.2f, 0.2f, 0.2f, 0.8f, 0.7f, 0.2f, 0.7f};
  Rsrc c;
  c.u32(1);
  unwrap_entry(c, key, 16, 8, uv2, idx);
  write(dir / "m/tile.obj.unwrap_cache", c.b);
  write(dir / "world.lmbake", lmbake_bytes(6, true, {{"..", "Tile"}}));
  write(dir / "world.tscn", lit_scene("Mesh", "m/tile.obj", "Tile"));
  const GodotSceneMeshes g = load_godot_scene((dir / "world.tscn").string());
  ASSERT_EQ(g.scene.instances.size(), 1u) << testing::PrintToString(g.notes);
  for (const std::string& n : g.notes) EXPECT_FALSE(contains(n, "by its triangles")) << n;
  ASSERT_EQ(g.scene.mesh.positions.size(), 12u);
  for (int k = 0; k < 12; ++k) EXPECT_FLOAT_EQ(g.scene.mesh.positions[size_t(k)], pos[size_t(k)]) << k;
  for (int v = 0; v < 4; ++v) {
    EXPECT_FLOAT_EQ(g.scene.mesh.uv[size_t(v * 2)], uv2[v * 2]) << v;
    EXPECT_FLOAT_EQ(g.scene.mesh.uv[size_t(v * 2 + 1)], 1.0f - uv2[v * 2 + 1]) << v;
  }
  // Imported without lightmap UV2: the user is named with the reason.
  write(dir / "m/tile.obj.import", import);
  try {
    load_godot_scene((dir / "world.tscn").string());
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_TRUE(contains(e.what(), "imported without Generate Lightmap UV2")) << e.what();
  }
  fs::remove_all(dir);
}
