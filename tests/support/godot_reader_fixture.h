// What the Godot reader's tests share (tests/unit and tests/integration godot_reader_test.cpp):
// writers of .lmbake, .tscn and unwrap-cache bytes, and a project instancing an FBX.
#pragma once
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

namespace ahd_fixture::godot_reader_fixture {

namespace fs = std::filesystem;
using namespace ::ahd;

inline bool contains(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

using ahd_test::Rsrc;

// world.tscn: a LightmapGI with res://world.lmbake and one node `node` of the resource `res` of type
// `type` (a PackedScene instanced, or a Mesh in a MeshInstance3D).
inline std::string lit_scene(const std::string& type, const std::string& res, const std::string& node) {
  return "[gd_scene load_steps=3 format=3]\n"
         "[ext_resource type=\"LightmapGIData\" path=\"res://world.lmbake\" id=\"1_lm\"]\n"
         "[ext_resource type=\"" +
         type + "\" path=\"res://" + res +
         "\" id=\"2_res\"]\n"
         "[node name=\"World\" type=\"Node3D\"]\n"
         "[node name=\"LightmapGI\" type=\"LightmapGI\" parent=\".\"]\nlight_data = ExtResource(\"1_lm\")\n" +
         (type == "Mesh"
              ? "[node name=\"" + node + "\" type=\"MeshInstance3D\" parent=\".\"]\nmesh = ExtResource(\"2_res\")\n"
              : "[node name=\"" + node + "\" parent=\".\" instance=ExtResource(\"2_res\")]\n");
}

// One unwrap-cache entry as godot_unwrap_cache.cpp reads it: the key, the size hint, four vertices
// (source vertices 0..3) with their UV2 (`uv2`: u, v pairs), the indices.
inline void unwrap_entry(Rsrc& c, const GodotUnwrapKey& key, uint32_t hint_w, uint32_t hint_h, const float* uv2,
                  const std::vector<uint32_t>& idx) {
  c.b.insert(c.b.end(), key.begin(), key.end());
  c.u32(hint_w), c.u32(hint_h), c.u32(4);
  for (uint32_t v = 0; v < 4; ++v) c.u32(v);
  for (int k = 0; k < 8; ++k) c.f32(uv2[k]);
  c.u32(uint32_t(idx.size()));
  for (uint32_t i : idx) c.u32(i);
}

// A LightmapGIData whose users are `users` (node paths by name; default one, "../Box"), each
// with the rectangle 0.25, 0.5, 0.5, 0.25 and slice 1, after a PackedVector4Array and a Callable
// property, written as format `format`. `uid_flag` false: flags without FORMAT_FLAG_UIDS (the uid
// field is written all the same).
inline std::vector<uint8_t> lmbake_bytes(uint32_t format, bool uid_flag = true,
                                  const std::vector<std::vector<std::string>>& users = {{"..", "Box"}}) {
  Rsrc r;
  r.b = {'R', 'S', 'R', 'C'};
  r.u32(0), r.u32(0), r.u32(4), r.u32(format >= 6 ? 3 : 2), r.u32(format);
  r.str("LightmapGIData");
  r.u64(0);                      // import metadata offset
  r.u32(uid_flag ? 3 : 1);       // named scene ids (+ uids)
  r.u64(0x1234567890abcdefull);  // uid
  for (int i = 0; i < 11; ++i) r.u32(0);
  std::vector<std::string> strings = {"extra", "later", "user_data", "uses_spherical_harmonics"};
  std::vector<std::vector<uint32_t>> ids;  // each user's names in the string table
  for (const std::vector<std::string>& path : users) {
    ids.emplace_back();
    for (const std::string& name : path) {
      const auto at = std::find(strings.begin(), strings.end(), name);
      ids.back().push_back(uint32_t(at - strings.begin()));
      if (at == strings.end()) strings.push_back(name);
    }
  }
  r.one_resource(strings, "LightmapGIData");
  r.u32(4);                       // properties
  r.u32(0), r.u32(53), r.u32(2);  // extra: PackedVector4Array of 2
  for (int i = 0; i < 8; ++i) r.f32(float(i));
  r.u32(1), r.u32(42);                                     // later: Callable (no payload)
  r.u32(3), r.u32(2), r.u32(1);                            // uses_spherical_harmonics: bool true
  r.u32(2), r.u32(30), r.u32(uint32_t(4 * users.size()));  // user_data: Array of 4 per user
  for (const std::vector<uint32_t>& path : ids) {
    r.u32(22), r.u16(uint16_t(path.size())), r.u16(0);  // NodePath
    for (uint32_t i : path) r.u32(i);
    r.u32(11), r.f32(0.25f), r.f32(0.5f), r.f32(0.5f), r.f32(0.25f);
    r.u32(3), r.u32(1);
    r.u32(3), r.u32(uint32_t(-1));
  }
  return r.b;
}

inline void write(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary) << text;
}
inline void write(const fs::path& p, const std::vector<uint8_t>& bytes) {
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

inline std::string lightmap_scene(const std::string& lmbake_res, const std::string& extra_nodes) {
  return "[gd_scene load_steps=3 format=3 uid=\"uid://abc\"]\n\n"
         "[ext_resource type=\"LightmapGIData\" uid=\"uid://def\" path=\"" +
         lmbake_res +
         "\" id=\"1_lm\"]\n\n"
         "[sub_resource type=\"BoxMesh\" id=\"BoxMesh_q1\"]\nadd_uv2 = true\nsize = Vector3(1, 2, 3)\n\n"
         "[node name=\"World\" type=\"Node3D\"]\n\n"
         "[node name=\"LightmapGI\" type=\"LightmapGI\" parent=\".\"]\nlight_data = ExtResource(\"1_lm\")\n\n" +
         extra_nodes;
}


// A project instancing tests/data/godot/handmade/room.fbx as "Room" (imported with Static
// Lightmaps), its one user the node Floor; the unwrap cache holds `entry` (a Godot-keyed entry).
inline fs::path fbx_project(const std::string& name, const std::vector<uint8_t>& cache, const std::string& import_extra = "") {
  const fs::path dir = ahd_test::temp_dir(name);
  write(dir / "project.godot", "config_version=5\n");
  fs::create_directories(dir / "m");
  fs::copy_file(ahd_test::test_data("godot/handmade/room.fbx"), dir / "m/room.fbx");
  write(dir / "m/room.fbx.import",
        "[remap]\n\nimporter=\"scene\"\n\n[params]\n\nmeshes/light_baking=2\n"
        "meshes/lightmap_texel_size=0.2\n" +
            import_extra);
  write(dir / "m/room.fbx.unwrap_cache", cache);
  write(dir / "world.lmbake", lmbake_bytes(6, true, {{"..", "Room", "Floor"}}));
  write(dir / "world.tscn", lit_scene("PackedScene", "m/room.fbx", "Room"));
  return dir;
}

// The cache Godot writes for room.fbx's FloorMesh, derived from modules/fbx/fbx_document.cpp's rules:
// the file's triangles (0,0,0) (2,0,0) (2,0,-1) and (0,0,0) (2,0,-1) (0,0,-1) are taken as c, b, a
// and their corners merged in order of first use: vertices (2,0,-1) (2,0,0) (0,0,0) (0,0,-1),
// triangles 0 1 2, 3 0 2; metres and Y up already (UnitScaleFactor 100); node scale 2.
inline const float kFbxUv2[8] = {0.9f, 0.1f, 0.9f, 0.6f, 0.1f, 0.6f, 0.1f, 0.1f};  // per vertex, v down
inline std::vector<uint8_t> room_cache(bool damage_key) {
  const std::vector<float> pos = {2, 0, -1, 2, 0, 0, 0, 0, 0, 0, 0, -1};
  const std::vector<float> nrm = {0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0};
  const std::vector<uint32_t> idx = {0, 1, 2, 3, 0, 2};
  const float scale[3] = {2, 2, 2};
  GodotUnwrapKey key = godot_unwrap_key(pos, nrm, idx, scale, 0.2f);
  if (damage_key) key[0] ^= 0xff;
  Rsrc c;
  c.u32(1);
  unwrap_entry(c, key, 16, 8, kFbxUv2, idx);
  return c.b;
}

}  // namespace ahd_fixture::godot_reader_fixture
