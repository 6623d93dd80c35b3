// Issue 44, the readers' side: every reader input through one opener (regular files only, a size
// bound per kind, read once), Godot project paths kept inside the project, work bounded by the
// input's size (scenes parsed once, shared strings, instanced geometry, overlaps counted, pages),
// Assimp's logger behind one lock. Large inputs are generated here, never committed.
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
#include "bad_input_round3_readers_fixture.h"

namespace fs = std::filesystem;
using namespace ahd;
using namespace ahd_fixture::bad_input_round3_readers_fixture;

// The opener: FIFOs and devices refused without blocking, a size bound per kind, the file noted.
TEST(BadInputRound3Readers, OpenerRefusesFifosAndDevicesAndBoundsTheSize) {
  const fs::path d = ahd_test::temp_dir("r3r_opener");
  const fs::path fifo = d / "pipe.tscn";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  expect_file_error([&] { read_input_bytes(fifo.string(), InputKind::kSceneText); }, fifo.string(), "not a regular file");
  expect_file_error([&] { read_input_bytes("/dev/zero", InputKind::kMesh); }, "/dev/zero", "not a regular file");
  spit(d / "big.tscn", std::string(100, 'x'));
  expect_file_error([&] { read_input_bytes((d / "big.tscn").string(), 99); }, (d / "big.tscn").string(),
                    "file too large (100 bytes, at most 99");
  expect_file_error([&] { read_input_bytes((d / "none.tscn").string(), InputKind::kSceneText); },
                    (d / "none.tscn").string(), "file not found");
  InputRecord rec;
  {
    RecordInputs scope(&rec);
    EXPECT_EQ(read_input_text((d / "big.tscn").string(), InputKind::kSceneText), std::string(100, 'x'));
  }
  EXPECT_EQ(rec.files, std::vector<std::string>{(d / "big.tscn").string()});
  EXPECT_GT(input_file_bound(InputKind::kMesh), input_file_bound(InputKind::kSceneText));

  // A scene instancing a FIFO, a project.godot that is a device: errors, never a read that blocks
  // or never ends.
  godot_project(d / "p", {"../A"});
  ASSERT_EQ(::mkfifo((d / "p" / "f.tscn").c_str(), 0600), 0);
  spit(d / "p" / "s.tscn", scene_text("[ext_resource type=\"PackedScene\" path=\"res://f.tscn\" id=\"f\"]\n",
                                       "[node name=\"A\" parent=\".\" instance=ExtResource(\"f\")]\n"));
  expect_file_error([&] { load_godot_scene((d / "p" / "s.tscn").string()); }, (d / "p" / "f.tscn").string(),
                    "not a regular file");
  fs::create_directories(d / "q");
  fs::create_symlink("/dev/zero", d / "q" / "project.godot");
  expect_file_error([&] { godot_project_version((d / "q" / "x.exr").string()); }, (d / "q" / "project.godot").string(),
                    "not a regular file");
  fs::remove_all(d);
}

// res://../, absolute paths and symlinks leaving the project: one error line naming the scene.
TEST(BadInputRound3Readers, GodotPathsLeavingTheProjectAreRefused) {
  const fs::path d = ahd_test::temp_dir("r3r_escape");
  const fs::path p = d / "p";
  godot_project(p, {"../A/B"});
  // A valid scene outside the project: before, it was read as if it were the project's.
  spit(d / "outside.tscn", std::string("[gd_scene format=3]\n[node name=\"R\" type=\"Node3D\"]\n"
                                       "[sub_resource type=\"BoxMesh\" id=\"b\"]\nadd_uv2 = true\n"
                                       "[node name=\"B\" type=\"MeshInstance3D\" parent=\".\"]\nmesh = SubResource(\"b\")\n"));
  const auto scene_naming = [&](const std::string& res) {
    spit(p / "s.tscn", scene_text("[ext_resource type=\"PackedScene\" path=\"" + res + "\" id=\"x\"]\n",
                                  "[node name=\"A\" parent=\".\" instance=ExtResource(\"x\")]\n"));
    return (p / "s.tscn").string();
  };
  for (const std::string& res : {std::string("res://../outside.tscn"), std::string("res://a/../../outside.tscn"),
                                 (d / "outside.tscn").string(), std::string("../outside.tscn")}) {
    SCOPED_TRACE(res);
    const std::string s = scene_naming(res);
    expect_file_error([&] { load_godot_scene(s); }, s, "outside the project");
  }
  // A symlink inside the project to a file outside it.
  fs::create_symlink(d / "outside.tscn", p / "link.tscn");
  const std::string s = scene_naming("res://link.tscn");
  expect_file_error([&] { load_godot_scene(s); }, s, "leads outside the project");
  // The same scene inside the project reads.
  fs::copy_file(d / "outside.tscn", p / "inside.tscn");
  const GodotSceneMeshes g = load_godot_scene(scene_naming("res://inside.tscn"));
  EXPECT_EQ(g.scene.instances.size(), 1u);
  fs::remove_all(d);
}

// 10⁴ instances of one scene: each scene file read and parsed once, listed once.
TEST(BadInputRound3Readers, InstancedScenesAreReadOnceAndListedOnce) {
  const fs::path d = ahd_test::temp_dir("r3r_instances");
  const int n = ahd_test::kSanitized ? 6 : 10;
  godot_project(d, {"../L3_0/L2_1/L1_2/L0_3/B", "../L3_1/L2_0/L1_0/L0_0/B"});
  spit(d / "l0.tscn", std::string("[gd_scene format=3]\n[sub_resource type=\"BoxMesh\" id=\"b\"]\nadd_uv2 = true\n"
                                  "[node name=\"R\" type=\"Node3D\"]\n"
                                  "[node name=\"B\" type=\"MeshInstance3D\" parent=\".\"]\nmesh = SubResource(\"b\")\n"));
  for (int level = 1; level <= 4; ++level) {
    std::string t = "[gd_scene format=3]\n[ext_resource type=\"PackedScene\" path=\"res://l" + std::to_string(level - 1) +
                    ".tscn\" id=\"i\"]\n";
    std::string nodes;
    for (int k = 0; k < n; ++k)
      nodes += "[node name=\"L" + std::to_string(level - 1) + "_" + std::to_string(k) +
               "\" parent=\".\" instance=ExtResource(\"i\")]\n";
    if (level < 4) spit(d / ("l" + std::to_string(level) + ".tscn"), t + "[node name=\"R\" type=\"Node3D\"]\n" + nodes);
    else spit(d / "s.tscn", scene_text("[ext_resource type=\"PackedScene\" path=\"res://l3.tscn\" id=\"i\"]\n", nodes));
  }
  const GodotSceneMeshes g = load_godot_scene((d / "s.tscn").string());
  EXPECT_EQ(g.scene.instances.size(), 2u) << testing::PrintToString(g.notes);
  // s.tscn, l3..l0, project.godot, s.lmbake: each once (before, every instance listed its file again).
  EXPECT_EQ(g.files.size(), 7u) << testing::PrintToString(g.files);
  std::vector<std::string> sorted = g.files;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(std::adjacent_find(sorted.begin(), sorted.end()), sorted.end());
  fs::remove_all(d);
}

// .lmbake: string references copied without bound (462 KB asked 13 GB), an int64 slice cast
// to int unchecked (undefined).
TEST(BadInputRound3Readers, LmbakeStringCopiesAreBoundedAndSliceIsCheckedAsInt64) {
  std::vector<User> users(4);
  for (User& u : users) u.names.assign(1000, 1);  // 1000 references to a 16 KB name each: 64 MB of copies
  const std::vector<uint8_t> b = lmbake_bytes({"user_data", std::string(16384, 'n')}, users);
  ASSERT_LT(b.size(), 40000u);
  expect_file_error([&] { parse_godot_lmbake(b.data(), b.size(), "x.lmbake"); }, "x.lmbake",
                    "string references copy more than");
  // A path of a few long names within the budget still reads.
  std::vector<User> few(2);
  for (User& u : few) u.names = {1, 1};
  EXPECT_EQ(parse_godot_lmbake(lmbake_bytes({"user_data", std::string(1000, 'n')}, few).data(),
                               lmbake_bytes({"user_data", std::string(1000, 'n')}, few).size(), "ok.lmbake")
                .users.size(),
            2u);
  User big;
  big.names = {1};
  big.slice = uint64_t(1) << 40, big.slice64 = true;
  const std::vector<uint8_t> s = lmbake_bytes({"user_data", "A"}, {big});
  expect_file_error([&] { parse_godot_lmbake(s.data(), s.size(), "s.lmbake"); }, "s.lmbake",
                    "has slice 1099511627776");
  big.slice = 3;
  const std::vector<uint8_t> ok = lmbake_bytes({"user_data", "A"}, {big});
  EXPECT_EQ(parse_godot_lmbake(ok.data(), ok.size(), "ok.lmbake").users.at(0).slice, 3);
}

// The scene's meshes go through the --mesh pre-check: a 20 000-deep chain (SIGSEGV before), an
// index out of range (dropped silently before).
TEST(BadInputRound3Readers, GodotSceneMeshesAreCheckedLikeMeshOption) {
  const fs::path d = ahd_test::temp_dir("r3r_scene_mesh");
  godot_project(d, {"../M/Node"});
  spit(d / "s.tscn", scene_text("[ext_resource type=\"PackedScene\" path=\"res://m.gltf\" id=\"m\"]\n",
                                "[node name=\"M\" parent=\".\" instance=ExtResource(\"m\")]\n"));
  std::string nodes = "[{\"name\": \"Node\", \"mesh\": 0, \"children\": [1]}";
  for (int i = 1; i < 20000; ++i) nodes += i + 1 < 20000 ? ",{\"children\": [" + std::to_string(i + 1) + "]}" : ",{}";
  spit(d / "m.gltf", gltf_uv2_triangle({0, 1, 2}, nodes + "]"));
  expect_file_error([&] { load_godot_scene((d / "s.tscn").string()); }, (d / "m.gltf").string(),
                    "deeper than 1024 levels");
  spit(d / "m.gltf", gltf_uv2_triangle({0, 1, 7}, "[{\"name\": \"Node\", \"mesh\": 0}]"));
  expect_file_error([&] { load_godot_scene((d / "s.tscn").string()); }, (d / "m.gltf").string(), "out of range");
  spit(d / "m.gltf", gltf_uv2_triangle({0, 1, 2}, "[{\"name\": \"Node\", \"mesh\": 0}]"));
  EXPECT_EQ(load_godot_scene((d / "s.tscn").string()).scene.instances.size(), 1u);
  fs::remove_all(d);
}

// Sparse accessors sized only by their count (1.4 KB asked 2.4 GB), geometry copied per node
// without bound (1.9 MB asked 10 GB).
TEST(BadInputRound3Readers, GltfAccessorCountsAndInstancedGeometryAreBounded) {
  const fs::path d = ahd_test::temp_dir("r3r_sparse");
  std::string g = gltf_uv2_triangle({0, 1, 2});
  // A fourth accessor: 30 million VEC3 with one sparse value, no buffer view, as a morph target.
  const std::string sparse =
      R"(, {"componentType": 5126, "count": 30000000, "type": "VEC3", "sparse": {"count": 1,
         "indices": {"bufferView": 2, "componentType": 5123}, "values": {"bufferView": 0}}}]})";
  const std::string morph = R"("indices": 2, "targets": [{"POSITION": 3}]})";
  std::string big = g.substr(0, g.rfind("]}")) + sparse;
  big.replace(big.find(R"("indices": 2})"), std::string(R"("indices": 2})").size(), morph);
  spit(d / "sparse.gltf", big);
  expect_file_error([&] { read_mesh_lightmap((d / "sparse.gltf").string(), 0); }, (d / "sparse.gltf").string(),
                    "accessor 3 has 30000000 elements");
  std::string over = g.substr(0, g.rfind("]}")) +
                     R"(, {"componentType": 5126, "count": 3, "type": "VEC3", "sparse": {"count": 9,
         "indices": {"bufferView": 2, "componentType": 5123}, "values": {"bufferView": 0}}}]})";
  over.replace(over.find(R"("indices": 2})"), std::string(R"("indices": 2})").size(), morph);
  spit(d / "over.gltf", over);
  expect_file_error([&] { read_mesh_lightmap((d / "over.gltf").string(), 0); }, (d / "over.gltf").string(),
                    "sparse count 9");
  // A mesh whose POSITION accessor claims 4096 vertices (checked against nothing else here),
  // instanced by 1100 nodes: 4.5 million vertices in the copies.
  std::string inst = gltf_uv2_triangle({0, 1, 2});
  inst.replace(inst.find(R"("count": 3, "type": "VEC3")"), std::string(R"("count": 3, "type": "VEC3")").size(),
               R"("count": 4096, "type": "VEC3")");
  std::string nodes = "[{\"children\": [";
  for (int i = 1; i <= 1100; ++i) nodes += (i > 1 ? "," : "") + std::to_string(i);
  nodes += "]}";
  for (int i = 1; i <= 1100; ++i) nodes += ",{\"mesh\": 0}";
  inst.replace(inst.find("[{\"mesh\": 0}]"), std::string("[{\"mesh\": 0}]").size(), nodes + "]");
  spit(d / "inst.gltf", inst);
  expect_file_error([&] { read_mesh_instances((d / "inst.gltf").string(), 0); }, (d / "inst.gltf").string(),
                    "instance more than 4194304 vertices");
  fs::remove_all(d);
}

// Every overlapping pair was kept as a string (390 KB → 3.4 GB): now counted, the first listed.
TEST(BadInputRound3Readers, PlacementOverlapsAreCountedNotListed) {
  MeshInstances scene;
  const size_t n = 2000;
  for (size_t i = 0; i < n; ++i) {
    MeshInstance inst;
    inst.node = "n" + std::to_string(i);
    inst.first_vertex = scene.mesh.positions.size() / 3, inst.vertices = 3;
    inst.first_index = scene.mesh.indices.size(), inst.indices = 3;
    for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) scene.mesh.positions.push_back(v);
    for (float v : {0.f, 0.f, 1.f, 0.f, 0.f, 1.f}) scene.mesh.uv.push_back(v);
    for (uint32_t k = 0; k < 3; ++k) scene.mesh.indices.push_back(uint32_t(inst.first_vertex + k));
    scene.instances.push_back(inst);
  }
  const PlacedMesh pm = place_instances(scene, identity_placements(scene), 0, "p.json");
  EXPECT_EQ(pm.overlap_count, n * (n - 1) / 2);
  ASSERT_EQ(pm.overlaps.size(), kMaxListedOverlaps);
  EXPECT_EQ(pm.overlaps[0], "'n0' and 'n1'");
  EXPECT_EQ(pm.placed.size(), n);
}

// Atlas pages: a fixed cost each, no bound before (2048 pages of 2x2 took 150 s).
TEST(BadInputRound3Readers, AtlasPageCountIsBounded) {
  const fs::path d = ahd_test::temp_dir("r3r_pages");
  const LayoutPreset layout = load_layout("godot4-packed");
  const fs::path exr = d / "lm.exr";
  spit(d / "lm.exr.import", std::string("[remap]\nimporter=\"2d_array_texture\"\n\n[params]\nslices/vertical=8192\n"
                                        "slices/horizontal=1\n"));
  // 2 x (2 x 4 x 2048) rows: 2048 pages of 2x2. The count is refused from the header and the import.
  ImageF img(2, 2 * 4 * 2048, 3);
  std::fill(img.data.begin(), img.data.end(), 0.25f);
  write_image(exr.string(), img);
  expect_file_error([&] { layout_pages(layout, exr.string(), 0); }, exr.string(), "2048 atlas pages");
  expect_file_error([&] { layout_pages(layout, exr.string(), 2048); }, exr.string(), "at most 256");
  fs::remove_all(d);
}

// A layout preset whose files[] name one image many times held a decoded copy each (504 KB → 3.6 GB).
TEST(BadInputRound3Readers, LayoutPresetCannotMultiplyAFile) {
  const fs::path d = ahd_test::temp_dir("r3r_preset");
  std::string files;
  for (int i = 0; i < 65; ++i) files += std::string(i ? "," : "") + R"({"pattern": "{base}.exr"})";
  spit(d / "many.json", R"({"name": "many", "coeffs": 4, "space": "tangent", "form": "radiance", "files": [)" + files +
                            R"(], "coefficients": [{"file": 0, "channels": ["R", "G", "B"]}]})");
  expect_file_error([&] { load_layout((d / "many.json").string()); }, (d / "many.json").string(), "65 files, at most 64");
  spit(d / "twice.json",
       std::string(R"({"name": "twice", "coeffs": 4, "space": "tangent", "form": "radiance",
        "files": [{"pattern": "{base}.exr"}, {"pattern": "{base}.exr"}],
        "coefficients": [{"file": 0, "channels": ["R", "G", "B"]}, {"file": 1, "channels": ["R", "G", "B"]}]})"));
  const LayoutPreset twice = load_layout((d / "twice.json").string());
  ImageF img(4, 4, 3);
  write_image((d / "lm.exr").string(), img);
  expect_file_error([&] { read_layout(twice, (d / "lm").string(), nullptr, nullptr); }, (d / "lm.exr").string(), "named twice");
  fs::remove_all(d);
}

// Assimp's process-wide logger was created and killed under a lock by one reader and used
// unlocked by another: a batch with --mesh crashed in 8 of 60 runs. 8 threads, several rounds.
TEST(BadInputRound3Readers, AssimpImportsInManyThreadsShareTheLoggerSafely) {
  const fs::path d = ahd_test::temp_dir("r3r_threads");
  spit(d / "ok.gltf", gltf_uv2_triangle({0, 1, 2}));
  spit(d / "bad.gltf", gltf_uv2_triangle({0, 1, 7}));
  const int rounds = ahd_test::kSanitized ? 2 : 6;
  for (int round = 0; round < rounds; ++round) {
    std::vector<std::thread> threads;
    std::vector<int> ok(8, 0);
    for (int t = 0; t < 8; ++t)
      threads.emplace_back([&, t] {
        for (int k = 0; k < 10; ++k) {
          try {
            if ((t + k) % 3 == 0) read_mesh_lightmap((d / "bad.gltf").string(), 0);
            else if ((t + k) % 3 == 1) ok[size_t(t)] += read_mesh_instances((d / "ok.gltf").string(), 0).instances.size() == 1;
            else ok[size_t(t)] += read_mesh_lightmap((d / "ok.gltf").string(), 0).indices.size() == 3;
          } catch (const Error& e) {
            ok[size_t(t)] += std::string(e.what()).find("out of range") != std::string::npos;
          }
        }
      });
    for (std::thread& th : threads) th.join();
    for (int t = 0; t < 8; ++t) EXPECT_EQ(ok[size_t(t)], 10) << "thread " << t << " round " << round;
  }
  fs::remove_all(d);
}

// A Unity scene saved with CRLF line ends placed 'Quad\r', which no node is called.
TEST(BadInputRound3Readers, UnitySceneWithCrlfLineEndsPlacesItsNodes) {
  const fs::path d = ahd_test::temp_dir("r3r_crlf");
  const std::string scene =
      "%YAML 1.1\r\n%TAG !u! tag:unity3d.com,2011:\r\n--- !u!1 &100\r\nGameObject:\r\n  m_Name: Quad\r\n"
      "--- !u!23 &200\r\nMeshRenderer:\r\n  m_GameObject: {fileID: 100}\r\n  m_LightmapIndex: 0\r\n"
      "  m_LightmapTilingOffset: {x: 0.5, y: 0.5, z: 0.25, w: 0}\r\n";
  spit(d / "s.unity", scene);
  const std::vector<Placement> p = read_placements((d / "s.unity").string());
  ASSERT_EQ(p.size(), 1u);
  EXPECT_EQ(p[0].node, "Quad");
  EXPECT_EQ(p[0].scale[0], 0.5);
  fs::remove_all(d);
}

// Nearly collinear primaries passed the determinant test and failed later as "not a 3x3 matrix".
TEST(BadInputRound3Readers, NearlyCollinearPrimariesAreNamedAsSuch) {
  SourceSpace s;
  s.name = "chromaticities";
  s.chromaticities = {0.3f, 0.3f, 0.4f, 0.4f, 0.5f, 0.50002f, 0.3127f, 0.3290f};
  expect_file_error([&] { working_space_matrix(s, "x.exr"); }, "x.exr", "nearly collinear primaries");
  s.chromaticities = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};  // Rec. 709's own: converts
  const Matrix3 m = working_space_matrix(s, "x.exr");
  EXPECT_NEAR(m[0][0], 1.0, 1e-3);
}

// A symlink loop on a reader's path: std::filesystem threw past the readers ("internal error",
// exit 2); now one line naming the file.
TEST(BadInputRound3Readers, SymlinkLoopIsOneErrorLine) {
  const fs::path d = ahd_test::temp_dir("r3r_loop");
  fs::create_symlink(d / "b", d / "a");
  fs::create_symlink(d / "a", d / "b");
  const std::string mesh = (d / "a" / "m.gltf").string();
  expect_file_error([&] { read_mesh_lightmap(mesh, 0); }, mesh, "symbolic links loop");
  expect_file_error([&] { read_input_bytes(mesh, InputKind::kMesh); }, mesh, "cannot open");
  fs::remove_all(d);
}
