// Issue 44's hostile reader inputs under a 4 GB address limit, each run by the command. In-process
// cases: tests/unit/bad_input_round3_readers_test.cpp.
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


namespace {

using ahd_test::LimitedRun;
using ahd_test::run_cli_limited;

}  // namespace

// The issue's bound: under a 4 GB address limit (ulimit -v 4000000), each generated hostile input
// under 1 MB gives one error line naming its file (or converts), under 1 GiB of memory. The wall
// time is printed for docs/robustness-input.md "Reader input files", not asserted.
TEST(BadInputRound3Readers, HostileInputsUnderFourGibStayUnderOneGib) {
  if (ahd_test::kSanitized) GTEST_SKIP() << "sanitizer builds reserve terabytes of shadow memory: RLIMIT_AS cannot apply";
  const fs::path d = ahd_test::temp_dir("r3r_ulimit");
  struct Input {
    std::string name;
    std::vector<std::string> args;
    std::string file;  // the file the error must name ("" = converts, exit 0)
  };
  std::vector<Input> inputs;
  // A Godot set of one page (8x8 layers) beside each project's scene.
  const auto godot_exr = [&](const fs::path& p) {
    ImageF img(8, 32, 3);
    std::fill(img.data.begin(), img.data.end(), 0.25f);
    write_image((p / "lm.exr").string(), img);
    spit(p / "lm.exr.import", std::string("[remap]\nimporter=\"2d_array_texture\"\n\n[params]\nslices/vertical=4\n"));
    return (p / "lm.exr").string();
  };
  const auto godot_run = [&](const std::string& name, const fs::path& p, const std::string& file) {
    const std::string exr = godot_exr(p);
    inputs.push_back({name, {"convert", exr, "--layout", "godot4-packed", "--godot-scene", (p / "s.tscn").string(),
                             "--allow-unplaced", "-o", (d / (name + ".ktx2")).string()}, file});
  };
  // res://../../dev/zero and a FIFO scene.
  godot_project(d / "zero", {"../A"});
  spit(d / "zero" / "s.tscn", scene_text("[ext_resource type=\"PackedScene\" path=\"res://../../../../../../../dev/zero\" id=\"z\"]\n",
                                         "[node name=\"A\" parent=\".\" instance=ExtResource(\"z\")]\n"));
  godot_run("dev-zero", d / "zero", (d / "zero" / "s.tscn").string());
  godot_project(d / "fifo", {"../A"});
  ASSERT_EQ(::mkfifo((d / "fifo" / "f.tscn").c_str(), 0600), 0);
  spit(d / "fifo" / "s.tscn", scene_text("[ext_resource type=\"PackedScene\" path=\"res://f.tscn\" id=\"f\"]\n",
                                         "[node name=\"A\" parent=\".\" instance=ExtResource(\"f\")]\n"));
  godot_run("fifo", d / "fifo", (d / "fifo" / "f.tscn").string());
  // 32^4 instances of one scene in a few KB.
  {
    const fs::path p = d / "inst";
    godot_project(p, {"../L3_0/L2_1/L1_2/L0_3/B"});
    spit(p / "l0.tscn", std::string("[gd_scene format=3]\n[sub_resource type=\"BoxMesh\" id=\"b\"]\nadd_uv2 = true\n"
                                    "[node name=\"R\" type=\"Node3D\"]\n"
                                    "[node name=\"B\" type=\"MeshInstance3D\" parent=\".\"]\nmesh = SubResource(\"b\")\n"));
    for (int level = 1; level <= 4; ++level) {
      std::string nodes;
      for (int k = 0; k < 32; ++k)
        nodes += "[node name=\"L" + std::to_string(level - 1) + "_" + std::to_string(k) +
                 "\" parent=\".\" instance=ExtResource(\"i\")]\n";
      const std::string ext = "[ext_resource type=\"PackedScene\" path=\"res://l" + std::to_string(level - 1) + ".tscn\" id=\"i\"]\n";
      if (level < 4) spit(p / ("l" + std::to_string(level) + ".tscn"), "[gd_scene format=3]\n" + ext + "[node name=\"R\" type=\"Node3D\"]\n" + nodes);
      else spit(p / "s.tscn", scene_text(ext, nodes));
    }
    godot_run("instances-32^4", p, "*");
  }
  // .lmbake: 100 users each a NodePath of 1000 references to a 4 KB name (400 MB of copies).
  {
    const fs::path p = d / "lm";
    godot_project(p, {"../A"});
    std::vector<User> users(100);
    for (User& u : users) u.names.assign(1000, 1);
    spit(p / "s.lmbake", lmbake_bytes({"user_data", std::string(4096, 'n')}, users));
    spit(p / "s.tscn", scene_text("", ""));
    godot_run("lmbake-paths", p, (p / "s.lmbake").string());
  }
  // A 20 000-deep node chain in the scene's mesh.
  {
    const fs::path p = d / "deep";
    godot_project(p, {"../M/Node"});
    spit(p / "s.tscn", scene_text("[ext_resource type=\"PackedScene\" path=\"res://m.gltf\" id=\"m\"]\n",
                                  "[node name=\"M\" parent=\".\" instance=ExtResource(\"m\")]\n"));
    std::string nodes = "[{\"name\": \"Node\", \"mesh\": 0, \"children\": [1]}";
    for (int i = 1; i < 20000; ++i) nodes += i + 1 < 20000 ? ",{\"children\": [" + std::to_string(i + 1) + "]}" : ",{}";
    spit(p / "m.gltf", gltf_uv2_triangle({0, 1, 2}, nodes + "]"));
    godot_run("scene-deep-gltf", p, (p / "m.gltf").string());
  }
  // --mesh: 15 000 overlapping instances (no placement), a sparse accessor of 30 M elements.
  {
    std::string nodes = "[{\"children\": [";
    for (int i = 1; i <= 15000; ++i) nodes += (i > 1 ? "," : "") + std::to_string(i);
    nodes += "]}";
    for (int i = 1; i <= 15000; ++i) nodes += ",{\"name\": \"n" + std::to_string(i) + "\", \"mesh\": 0}";
    spit(d / "overlap.gltf", gltf_uv2_triangle({0, 1, 2}, nodes + "]"));
    const std::string exr = godot_exr(d);
    inputs.push_back({"mesh-overlaps", {"convert", exr, "--layout", "godot4-packed", "--mesh", (d / "overlap.gltf").string(),
                                        "-o", (d / "o1.ktx2").string()}, (d / "overlap.gltf").string()});
    std::string g = gltf_uv2_triangle({0, 1, 2});
    std::string big = g.substr(0, g.rfind("]}")) +
                      R"(, {"componentType": 5126, "count": 200000000, "type": "VEC3", "sparse": {"count": 1,
         "indices": {"bufferView": 2, "componentType": 5123}, "values": {"bufferView": 0}}}]})";
    big.replace(big.find(R"("indices": 2})"), std::string(R"("indices": 2})").size(),
                R"("indices": 2, "targets": [{"POSITION": 3}]})");
    spit(d / "sparse.gltf", big);
    inputs.push_back({"mesh-sparse", {"convert", exr, "--layout", "godot4-packed", "--mesh", (d / "sparse.gltf").string(),
                                      "-o", (d / "o2.ktx2").string()}, (d / "sparse.gltf").string()});
  }
  // The editor-export search: 3000 nodes each holding a mesh node, 8000 users (110 s, 3.1 GB before).
  {
    const fs::path p = d / "export";
    fs::create_directories(p);
    std::string nodes = "[{\"name\": \"Root\", \"children\": [";
    for (int i = 1; i <= 3000; ++i) nodes += (i > 1 ? "," : "") + std::to_string(i);
    nodes += "]}";
    for (int i = 1; i <= 3000; ++i) nodes += ",{\"name\": \"c" + std::to_string(i) + "\", \"children\": [" + std::to_string(3000 + i) + "]}";
    for (int i = 1; i <= 3000; ++i) nodes += ",{\"name\": \"m\", \"mesh\": 0}";
    spit(p / "export.gltf", gltf_uv2_triangle({0, 1, 2}, nodes + "]"));
    std::vector<std::string> strings = {"user_data", "..", "m"};
    for (int i = 1; i <= 3000; ++i) strings.push_back("c" + std::to_string(i));
    std::vector<User> users(8000);
    for (size_t k = 0; k < users.size(); ++k) users[k].names = {1, uint32_t(3 + (k * 7919) % 3000), 2};
    const std::string exr = godot_exr(p);
    spit(p / "lm.lmbake", lmbake_bytes(strings, users));
    inputs.push_back({"export-search", {"convert", exr, "--layout", "godot4-packed", "--godot-scene", (p / "export.gltf").string(),
                                        "--allow-unplaced", "-o", (d / "o5.ktx2").string()}, "*"});
  }
  // 2048 atlas pages of 2x2.
  {
    fs::create_directories(d / "pages");
    ImageF img(2, 2 * 4 * 2048, 3);
    std::fill(img.data.begin(), img.data.end(), 0.25f);
    write_image((d / "pages" / "lm.exr").string(), img);
    spit(d / "pages" / "lm.exr.import",
         std::string("[remap]\nimporter=\"2d_array_texture\"\n\n[params]\nslices/vertical=8192\n"));
    inputs.push_back({"pages-2048", {"convert", (d / "pages" / "lm.exr").string(), "--layout", "godot4-packed", "-o",
                                     (d / "o3.ktx2").string()}, (d / "pages" / "lm.exr").string()});
  }
  // A layout preset naming one image 8000 times.
  {
    std::string files;
    for (int i = 0; i < 8000; ++i) files += std::string(i ? "," : "") + R"({"pattern": "{base}.exr"})";
    spit(d / "many.json", R"({"name": "many", "coeffs": 4, "space": "tangent", "form": "radiance", "files": [)" + files +
                              R"(], "coefficients": [{"file": 0, "channels": ["R", "G", "B"]}]})");
    ImageF img(64, 64, 3);
    write_image((d / "p.exr").string(), img);
    inputs.push_back({"preset-copies", {"convert", (d / "p").string(), "--layout", (d / "many.json").string(), "-o",
                                        (d / "o4.ktx2").string()}, (d / "many.json").string()});
  }
  for (const Input& in : inputs) {
    SCOPED_TRACE(in.name);
    const LimitedRun r = run_cli_limited(in.args, d / (in.name + ".log"), rlim_t(4000000) * 1024);
    std::printf("%-16s exit %d, %.2f s, peak RSS %ld KiB: %s", in.name.c_str(), r.exit_code, r.seconds, r.peak_rss_kb,
                r.output.substr(0, 200).c_str());
    if (in.file != "*") {
      EXPECT_EQ(r.exit_code, 1) << r.output;
      EXPECT_EQ(r.output.rfind("ahdpack: error: " + in.file + ": ", 0), 0u) << r.output;
    } else {
      EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1) << r.output;
    }
    EXPECT_EQ(r.output.find("out of memory"), std::string::npos) << r.output;
    EXPECT_LT(r.peak_rss_kb, 1024L * 1024) << r.output;
  }
  fs::remove_all(d);
}
