// What a conversion's input knows of its scene, for engines: the lightmapped instances with their
// atlas page and rectangle (the manifest's "instances"), and the placed scene as glTF (`ahdpack
// scene`): every instance's mesh in world space, its lightmap UVs in atlas space. From a Godot
// project (--godot-scene, or the scene found beside the EXR) or --mesh with --placement.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "bakers/bake_input.h"
#include "pipeline/manifest.h"
#include "scene/mesh_io.h"

namespace ahd {

// The instances of the scene `a` was read with (call after read_bake_pages: a.godot is loaded
// then), in the scene's order, atlas rectangles in glTF's UV convention (v down). Empty when the
// input has no placement (the canonical EXR, a mesh without --placement, the sample). Throws
// ahd::Error("<file>: <cause>") for an unreadable placement file.
std::vector<ManifestInstance> bake_instances(const BakeInput& a);

struct SceneGltf {
  std::vector<uint8_t> glb;
  size_t instances = 0, triangles = 0;
  int pages = 1;
};

// The placed scene of `a` as one mesh for a viewer: every placed instance's triangles in world
// space with their lightmap UVs moved to atlas space (MeshTriangles' convention, v up: the atlas
// row of v is (1 − v) · height), and each triangle's atlas page. Empty (no triangles) when the
// input has no placed scene. Call after read_bake_input, as bake_scene_gltf. Throws ahd::Error for
// an unreadable mesh or placement file.
struct PlacedSceneMesh {
  MeshTriangles mesh;
  std::vector<int32_t> triangle_page;  // one per triangle of mesh.indices
  size_t instances = 0;
};
PlacedSceneMesh bake_placed_mesh(const BakeInput& a);

// The placed scene of `a` (read as read_bake_input reads it) as glTF binary: one node per
// lightmapped instance named by its node path, world-space POSITION and NORMAL (glTF axes, as the
// meshes are read), TEXCOORD_0 = its own lightmap UVs, TEXCOORD_1 = the same in atlas space (where
// the planes are sampled), node extras {"ahd_page": page, "ahd_uv_scale", "ahd_uv_offset"}.
// Deterministic bytes. Throws ahd::Error when the input has no placed scene.
SceneGltf bake_scene_gltf(const BakeInput& a);

}  // namespace ahd
