// What the third round's reader tests share (tests/unit and tests/integration bad_input_round3_readers_test.cpp).
#pragma once
#include <gtest/gtest.h>
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <string>
#include <thread>
#include <vector>
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include "expect_error.h"
#include "limited_run.h"
#include "fixture_writers.h"
#include "bakers/baker_layout.h"
#include "bakers/godot/godot_import.h"
#include "bakers/godot/godot_lmbake.h"
#include "bakers/godot/godot_scene.h"
#include "bakers/layout_pages.h"
#include "cli_runner.h"
#include "core/error.h"
#include "core/image.h"
#include "file_bytes.h"
#include "files/input_file.h"
#include "files/input_record.h"
#include "image/colour_space.h"
#include "image/image_io.h"
#include "sanitized.h"
#include "scene/mesh_io.h"
#include "scene/placement.h"
#include "scene/placement_io.h"

namespace ahd_fixture::bad_input_round3_readers_fixture {

namespace fs = std::filesystem;
using namespace ::ahd;

using ahd_test::spit;

using ahd_test::expect_file_error;

using ahd_test::Rsrc;

struct User {
  std::vector<uint32_t> names;  // string-table indices of the NodePath's names
  float rect[4] = {0, 0, 1, 1};
  uint64_t slice = 0;
  bool slice64 = false;  // the slice as an int64 value
};

// A LightmapGIData (format 5) with the string table `strings` (index 0 must be "user_data") and
// `users`.
inline std::vector<uint8_t> lmbake_bytes(const std::vector<std::string>& strings, const std::vector<User>& users) {
  Rsrc r;
  r.b = {'R', 'S', 'R', 'C'};
  r.u32(0), r.u32(0), r.u32(4), r.u32(2), r.u32(5);
  r.str("LightmapGIData");
  r.u64(0);  // import metadata offset
  r.u32(1);  // flags
  r.u64(0);  // uid
  for (int i = 0; i < 11; ++i) r.u32(0);
  r.one_resource(strings, "LightmapGIData");
  r.u32(1);                                                 // properties
  r.u32(0), r.u32(30), r.u32(uint32_t(4 * users.size()));  // user_data: Array of 4 per user
  for (const User& u : users) {
    r.u32(22), r.u16(uint16_t(u.names.size())), r.u16(0);  // NodePath
    for (uint32_t i : u.names) r.u32(i);
    r.u32(11);
    for (float v : u.rect) r.f32(v);
    if (u.slice64) r.u32(40), r.u64(u.slice);
    else r.u32(3), r.u32(uint32_t(u.slice));
    r.u32(3), r.u32(uint32_t(-1));
  }
  return r.b;
}

// The one-triangle glTF with TEXCOORD_1 (the Godot route reads UV2).
inline std::string gltf_uv2_triangle(const std::array<uint16_t, 3>& idx, const std::string& nodes_json = "[{\"mesh\": 0}]") {
  return ahd_test::gltf_triangle(idx, nodes_json, 0, true);
}

// A Godot scene whose LightmapGI bakes res://s.lmbake, with `ext` extra ext_resource lines and
// `nodes` after the LightmapGI.
inline std::string scene_text(const std::string& ext, const std::string& nodes) {
  return "[gd_scene load_steps=3 format=3]\n"
         "[ext_resource type=\"LightmapGIData\" path=\"res://s.lmbake\" id=\"lm\"]\n" +
         ext +
         "[node name=\"World\" type=\"Node3D\"]\n"
         "[node name=\"LightmapGI\" type=\"LightmapGI\" parent=\".\"]\nlight_data = ExtResource(\"lm\")\n" +
         nodes;
}

// A project in `d`: project.godot, s.lmbake with one user per path of `users` (names split at '/').
inline void godot_project(const fs::path& d, const std::vector<std::string>& users) {
  fs::create_directories(d);
  spit(d / "project.godot", std::string("config_version=5\n"));
  std::vector<std::string> strings = {"user_data"};
  std::vector<User> us;
  for (const std::string& path : users) {
    User u;
    size_t at = 0;
    while (at <= path.size()) {
      const size_t cut = std::min(path.find('/', at), path.size());
      const std::string name = path.substr(at, cut - at);
      const auto it = std::find(strings.begin(), strings.end(), name);
      u.names.push_back(uint32_t(it - strings.begin()));
      if (it == strings.end()) strings.push_back(name);
      at = cut + 1;
    }
    us.push_back(u);
  }
  spit(d / "s.lmbake", lmbake_bytes(strings, us));
}

}  // namespace ahd_fixture::bad_input_round3_readers_fixture
