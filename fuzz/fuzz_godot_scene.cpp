// Godot's scene-side readers on untrusted bytes (issue 44): byte 0 picks the reader, the rest is the
// file. 0: a .tscn (parse_godot_tscn); 1: a .lmbake (parse_godot_lmbake: users, NodePaths, slices);
// 2: a binary resource's main resource (parse_godot_binary_resource: .res/.mesh); 3: an .obj mesh
// as Godot imports it (parse_godot_obj_mesh). Seeds: the small Godot files of tests/data/godot
// (scripts/fuzz.sh).
#include "bakers/godot/godot_lmbake.h"
#include "bakers/godot/godot_obj.h"
#include "bakers/godot/godot_tscn.h"
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const uint8_t* b = data + 1;
  const size_t n = size - 1;
  const std::string text(reinterpret_cast<const char*>(b), n);
  ahd_fuzz::expect_clean([&] {
    switch (data[0] % 4) {
      case 0: {
        const ahd::GodotTscn t = ahd::parse_godot_tscn(text, "f.tscn");
        if (t.nodes.empty()) __builtin_trap();  // "a file without a node" is an error, not an empty scene
        for (const ahd::GodotTscnNode& node : t.nodes) (void)t.find_ext(node.instance);
        break;
      }
      case 1: {
        const ahd::GodotLightmapData d = ahd::parse_godot_lmbake(b, n, "f.lmbake");
        for (const ahd::GodotLightmapUser& u : d.users)
          if (u.slice < 0) __builtin_trap();  // slices are range-checked before the cast
        break;
      }
      case 2:
        (void)ahd::parse_godot_binary_resource(b, n, "f.res");
        break;
      default: {
        const float scale[3] = {1, 1, 1}, offset[3] = {0, 0, 0};
        (void)ahd::parse_godot_obj_mesh(text, "f.obj", scale, offset);
      }
    }
  });
  return 0;
}
