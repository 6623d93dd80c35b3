// Godot ArrayMesh resources (bakers/godot/godot_array_mesh): byte 0 picks the reader, the rest is
// the input. 0: a `_surfaces` value (godot_array_mesh_text); 1: a whole .tres/.res/.mesh
// (godot_mesh_resource_file); 2: a .tscn's inline mesh with id "A" (godot_text_sub_resource_mesh).
// Seeds: the Godot-written files of tests/data/godot/generated (scripts/fuzz.sh).
#include "bakers/godot/godot_array_mesh.h"
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const std::string in(reinterpret_cast<const char*>(data + 1), size - 1);
  const int which = data[0] % 3;
  ahd_fuzz::expect_clean([&] {
    if (which == 0) ahd::godot_array_mesh_text(in, "f.tscn");
    else if (which == 1) ahd::godot_mesh_resource_file(in, "f.mesh");
    else ahd::godot_text_sub_resource_mesh(in, "A", "f.tscn");
  });
  return 0;
}
