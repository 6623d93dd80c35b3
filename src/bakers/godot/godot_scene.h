// A Godot project's baked scene as meshes placed in its lightmap atlas, from the files a Godot
// repository holds: the scene (.tscn, nested scenes instanced by ext_resource), the LightmapGI's
// .lmbake (bakers/godot/godot_lmbake.h: each user's node path, page and rectangle), the meshes (.glb/.gltf
// through Assimp) and their lightmap UVs — the importer's cache NAME.glb.unwrap_cache
// (bakers/godot/godot_unwrap_cache.h; each mesh's entry found by Godot's own key,
// bakers/godot/godot_unwrap_key.h) for meshes imported with meshes/light_baking=2, or the file's
// second UV set (TEXCOORD_1, e.g. the editor's glTF export) — and the meshes a scene defines or
// names as resources (`mesh = SubResource/ExtResource(…)`, bakers/godot/godot_mesh_resource.h).
//
// FBX instances (Godot >= 4.3 imports .fbx itself, through ufbx) are read through Assimp and
// rebuilt as Godot's FBX importer builds them (bakers/godot/godot_fbx.h); .obj mesh resources as
// its OBJ importer builds them (bakers/godot/godot_obj.h).
//
// Godot's conventions used (from its scene importer and glTF module): an imported .glb is a
// Node3D named after the file holding the glTF scene's root nodes; node names have '.', ':', '@',
// '/', '"' and '%' replaced by '_'; the unwrap cache's source vertices index the mesh's surfaces
// concatenated in glTF primitive order (the accessor's vertex order, which Assimp keeps).
#pragma once
#include <string>
#include <vector>

#include "scene/mesh_io.h"
#include "scene/placement.h"

namespace ahd {

// A lightmap user of the .lmbake that the reader could not place (its mesh or its node is not
// reproduced outside Godot): its atlas rectangle is known, its geometry is not.
struct GodotUnplacedUser {
  std::string node;               // the user's node path as the .lmbake stores it (GridMap: "path [cell N]")
  int page = 0;                   // atlas slice
  double rect[4] = {0, 0, 0, 0};  // x, y, width, height: atlas fraction, v down (Godot's uv_scale)
  std::string why;                // the cause, with the remedy when there is one
};

struct GodotSceneMeshes {
  MeshInstances scene;               // one instance per placed user, world space, UV2 v up (OBJ convention)
  std::vector<Placement> placements; // per instance: page = slice, atlas_uv = uv2 · size + position (v up)
  std::string lmbake;                // the .lmbake read
  std::vector<std::string> files;    // every file read, in order (for dependency files)
  std::vector<std::string> notes;    // what was read and what was left out: each user without a mesh, and why
  int users = 0;                     // users in the .lmbake
  std::vector<GodotUnplacedUser> unplaced;  // every user not among the instances, in .lmbake order
};

// Loads `tscn` (its project: the nearest project.godot above it resolves res:// paths), the
// LightmapGI's light_data (`lmbake` overrides it; "" = as the scene says), every instanced scene
// and mesh. Throws ahd::Error("<file>: <cause>") for an unreadable scene, lmbake or mesh, a scene
// without a LightmapGI, a cache entry inconsistent with its mesh, or no user with a mesh.
GodotSceneMeshes load_godot_scene(const std::string& tscn, const std::string& lmbake = "");

// A baked scene exported from Godot's editor as glTF (Scene > Export As > glTF 2.0: the node tree
// with its names, UV2 as TEXCOORD_1), placed by `lmbake`: for a project without unwrap caches. The
// users' node paths are resolved from the node under which most of them find a mesh (the export
// may leave the LightmapGI node out). Throws ahd::Error("<file>: <cause>") like load_godot_scene,
// and when no user is found in the file.
GodotSceneMeshes load_godot_export(const std::string& gltf, const std::string& lmbake);

// The scene that baked `exr` (Godot's NAME.exr): the .tscn of its project (the nearest
// project.godot at or above the EXR; without one, the EXR's folder alone) whose LightmapGI's
// light_data is the NAME.lmbake beside the EXR. The walk is bounded (12 levels, 20 000 entries; no
// hidden folders such as .godot/, no symlinked folders, no nested projects). Paths are spelt as
// `exr` is (relative stays relative). "" when there is none; when several bake it, the one beside
// the EXR, else ahd::Error("<lmbake>: N scenes bake it (a, b): name the one to read with --godot-scene").
// Binary scenes (.scn) are not read.
std::string find_godot_scene(const std::string& exr);

}  // namespace ahd
