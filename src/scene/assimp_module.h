// Assimp behind dlopen: mesh files (.gltf, .glb, .obj, .fbx) are parsed by a small module
// (libahd_assimp.so, src/assimp/module.cpp) loaded on first use, so a process that reads no mesh
// never maps Assimp and its dependencies (docs/performance-real.md "Assimp on first use"). The
// module hands back a plain copy of what src/scene and src/bakers/godot read of Assimp's aiScene
// (ImportedScene: floats as Assimp holds them, ai_real = float, so every product computed from
// them is the same as from aiScene's), and nothing of Assimp's types crosses into ahdpack. Every
// file Assimp opens comes from the caller's AssimpFiles (the opener and the input record stay on
// this side, scene/mesh_io.cpp); every check and every message but Assimp's own stays here too.
// Internal to src/scene and src/bakers.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace ahd {

// Bumped whenever AssimpModule or ImportedScene changes: a module of another build is refused.
constexpr int kAssimpModuleAbi = 1;

// Import flags, mapped to Assimp's post-processing steps (aiProcess_*) and properties in the module.
enum : unsigned {
  kImportTriangulate = 1u << 0,            // aiProcess_Triangulate
  kImportPreTransformVertices = 1u << 1,   // aiProcess_PreTransformVertices
  kImportValidateDataStructure = 1u << 2,  // aiProcess_ValidateDataStructure
  kImportFbxNoPivots = 1u << 3,            // AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS = false
};

// aiPrimitiveType bits (ImportedMesh::primitive_types), as Assimp numbers them.
enum : unsigned { kPrimitivePoint = 0x1, kPrimitiveLine = 0x2, kPrimitiveTriangle = 0x4, kPrimitivePolygon = 0x8 };

// AI_MAX_NUMBER_OF_TEXTURECOORDS.
constexpr unsigned kImportedUvSets = 8;

// An aiMesh: per-vertex arrays (empty when the mesh has none: aiMesh::HasNormals() and the like are
// `!normals.empty()`), faces as Assimp gives them.
struct ImportedMesh {
  std::string name;                                    // mName
  unsigned primitive_types = 0;                        // mPrimitiveTypes
  unsigned vertices = 0;                               // mNumVertices
  std::vector<float> positions;                        // x, y, z per vertex
  std::vector<float> normals;                          // x, y, z per vertex
  std::vector<float> tangents, bitangents;             // x, y, z per vertex; both or neither
  std::array<std::vector<float>, kImportedUvSets> uv;  // u, v per vertex (mTextureCoords[k] x, y)
  unsigned uv_sets = 0;                                // GetNumUVChannels(): the sets present from set 0 on
  std::vector<float> colors;                           // mColors[0]: r, g, b, a per vertex
  std::vector<uint32_t> face_first;  // faces: face f's corners are indices[face_first[f] .. face_first[f + 1])
  std::vector<uint32_t> indices;
  size_t faces() const { return face_first.empty() ? 0 : face_first.size() - 1; }
  unsigned face_size(size_t f) const { return face_first[f + 1] - face_first[f]; }
  const uint32_t* face(size_t f) const { return indices.data() + face_first[f]; }
};

// An aiNode: nodes[0] is the root; children and meshes are indices into ImportedScene's vectors.
struct ImportedNode {
  std::string name;                 // mName
  std::array<float, 16> transform{};  // mTransformation: rows a1 a2 a3 a4, b1 .., c1 .., d1 ..
  int parent = -1;                  // mParent (−1 for the root)
  std::vector<unsigned> children;   // mChildren, in order
  std::vector<unsigned> meshes;     // mMeshes, in order
};

struct ImportedScene {
  std::vector<ImportedNode> nodes;  // never empty after a successful import
  std::vector<ImportedMesh> meshes;
  // mMetaData entries of the scene (FBX: UpAxis, UnitScaleFactor, …) of the types read here,
  // by type as aiMetadata::Get<T> matches them (the first entry of a key).
  std::map<std::string, int32_t> meta_int32;
  std::map<std::string, float> meta_float;
  std::map<std::string, double> meta_double;
};

// Where Assimp's file system gets its files: callbacks into the main program (which reads each
// file once through its opener and notes it in the input record). Neither throws.
struct AssimpFiles {
  void* ctx = nullptr;
  bool (*exists)(void* ctx, const std::string& path) = nullptr;
  // The bytes of `path`, owned by ctx and kept until the import returns; false when unreadable
  // (ctx keeps why).
  bool (*read)(void* ctx, const std::string& path, const uint8_t** data, size_t* size) = nullptr;
};

// The module's calls. None throws.
struct AssimpModule {
  int abi;
  // Assimp's ReadFile(path, flags) over `files`, under the module's lock around Assimp's
  // process-wide logger; the scene copied into *out. *dropped_faces: the glTF importer warned that
  // it dropped faces with out-of-range indices (set even when the import fails). False when Assimp
  // returned no scene (or one without a root node) or anything threw: *err is Assimp's message.
  bool (*import)(const std::string& path, unsigned flags, const AssimpFiles& files, ImportedScene* out,
                 bool* dropped_faces, std::string* err);
};

// The module, loaded on first call (thread safe), found as files/modules.h says. Throws
// ahd::Error("<why>: needs Assimp, whose module cannot be loaded (<module path>: <cause>)"), `why`
// being the file that needed it. Built with AHD_ASSIMP_MODULE=OFF, the module's code is part of
// ahdpack and this returns its table directly.
const AssimpModule& assimp_module(const std::string& why);

}  // namespace ahd
