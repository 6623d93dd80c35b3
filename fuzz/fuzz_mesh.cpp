// The mesh reader (Assimp's parser, then our validation of indices, UVs and normals). Byte 0 picks
// the format (.obj / .gltf / .glb), the rest is the file. Seeds: the small meshes of scripts/fuzz.sh.
#include "fuzz_common.h"
#include "scene/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  static const char* kExt[3] = {".obj", ".gltf", ".glb"};
  const std::string path = ahd_fuzz::write_temp(data + 1, size - 1, kExt[data[0] % 3]);
  ahd_fuzz::expect_clean([&] { ahd::read_mesh_lightmap(path, -1); });
  return 0;
}
