// Meshes in (Assimp): the triangles, vertex normals and lightmap UVs a lightmap was baked on, for
// mesh/lightmap_raster. The only place that touches mesh files.
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "scene/assimp_module.h"
#include "scene/lightmap_raster.h"

namespace ahd {

// The most vertices and indices a scene's instances hold in all (each placed copy of a mesh counts):
// far above a real lightmapped scene, and about 0.5 GB of geometry in the copies made of them
// (docs/robustness-input.md "Reader input files").
constexpr size_t kMaxSceneVertices = size_t(1) << 22;
constexpr size_t kMaxSceneIndices = size_t(1) << 24;

// The files an import read (the mesh and those it pulls in: a .gltf's .bin, an .obj's .mtl), each
// through the opener (files/input_file.h) once into memory: regular files only, bounded, noted in
// the current input record (files/input_record.h). Assimp's file system reads them from here.
class MeshFileReads {
 public:
  // The bytes of `file`, read on first use. Throws ahd::Error.
  const std::vector<uint8_t>& load(const std::string& file);
  bool has(const std::string& file) const { return files_.count(file) != 0; }
  std::string error;  // the first file Assimp could not read, for the message

 private:
  std::map<std::string, std::vector<uint8_t>> files_;
};

// The one Assimp import of src/scene and src/bakers (through the module, scene/assimp_module.h:
// `flags` are its kImport* flags): `path` read once through the opener into `reads` (a local set
// when null), a glTF checked from those same bytes (scene/gltf_precheck.h: node depth, buffer
// sizes, accessor counts, instanced geometry) and then parsed by Assimp from them, so a file swapped
// in between is never seen. The module listens to Assimp's process-wide logger under one lock for
// the glTF importer's dropped out-of-range faces, refused here as OBJ's are. Throws
// ahd::Error("<path>: <cause>"), also when the module cannot be loaded. Thread safe.
ImportedScene import_mesh_file(const std::string& path, unsigned flags, MeshFileReads* reads = nullptr);

// What read_mesh_lightmap found, for messages and reports.
struct MeshReadInfo {
  int uv_set = 0;      // the UV set used
  int uv_sets = 0;     // UV sets of the scene (the fewest any mesh has)
  int meshes = 0;      // meshes with triangles, merged
  size_t triangles = 0;
};

// Reads a .gltf, .glb or .obj file: every mesh of the scene, node transforms applied
// (positions by the node matrix, normals by its inverse transpose, renormalised), merged into one
// triangle list; non-triangle primitives (points, lines) are dropped, polygons triangulated.
// `uv_set`: the lightmap UV set (glTF TEXCOORD_n, n = uv_set); −1 = the default rule: the second
// set when the meshes have ≥ 2 (the lightmap UVs by convention: set 0 holds the texture UVs), else
// the first. When some meshes have 1 set and others ≥ 2 the default is ambiguous and refused.
// UVs come back in the OBJ convention (v up) for both formats (see scene/lightmap_raster.h).
// Normals: the file's, or all-zero for a mesh without them (the rasteriser then uses face
// normals); `normals` is empty when no mesh has any.
// Throws ahd::Error("<path>: <cause>"): file not found, other extension, unreadable or invalid
// file (Assimp's message), no triangles, no UVs, the requested set missing (naming how many there
// are). Indices are validated. The parsing itself is Assimp's: fine for a user's own assets, not
// hardened against deliberately hostile files.
MeshTriangles read_mesh_lightmap(const std::string& path, int uv_set, MeshReadInfo* info = nullptr);

}  // namespace ahd

namespace ahd {

// One placed copy of a mesh in the scene (a node holding a mesh): its vertices and triangles
// inside MeshInstances::mesh, for per-instance lightmap placement (scene/placement.h).
struct MeshInstance {
  std::string node;             // the node's name (glTF node name, Unity GameObject name on export)
  std::vector<std::string> meshes;  // the names of its meshes (glTF mesh names: Bevy's GltfMeshName)
  size_t first_vertex = 0, vertices = 0;
  size_t first_index = 0, indices = 0;
};

struct MeshInstances {
  MeshTriangles mesh;  // every instance's triangles, node transforms applied (as read_mesh_lightmap)
  std::vector<MeshInstance> instances;
};

// Like read_mesh_lightmap, but keeps the scene's instances apart: every node that holds meshes is
// one instance (its meshes merged), transformed by its accumulated node matrix (normals by the
// inverse transpose, renormalised), so instances that share a mesh get their own vertices and can
// be placed in the atlas one by one. UV sets and errors as read_mesh_lightmap.
MeshInstances read_mesh_instances(const std::string& path, int uv_set, MeshReadInfo* info = nullptr);

}  // namespace ahd
