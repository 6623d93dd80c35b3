#include "scene/mesh_io.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <map>
#include <vector>

#include "core/error.h"
#include "scene/gltf_precheck.h"
#include "files/input_file.h"
#include "files/utf8_path.h"

namespace ahd {
namespace fs = std::filesystem;

namespace {

std::string one_line(std::string s) {
  std::replace(s.begin(), s.end(), '\n', ' ');
  std::replace(s.begin(), s.end(), '\r', ' ');
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

std::string mesh_name(const ImportedMesh& m, unsigned index) {
  return !m.name.empty() ? "'" + m.name + "'" : "#" + std::to_string(index);
}

bool has_triangles(const ImportedMesh& m) { return (m.primitive_types & kPrimitiveTriangle) != 0; }

// Assimp's file system (in the module) over `MeshFileReads`: neither callback throws.
bool assimp_file_exists(void* ctx, const std::string& file) {
  try {
    if (static_cast<const MeshFileReads*>(ctx)->has(file)) return true;
    std::error_code ec;
    return fs::is_regular_file(fs_path(file), ec);
  } catch (...) {
    return false;
  }
}

bool assimp_file_read(void* ctx, const std::string& file, const uint8_t** data, size_t* size) {
  auto* reads = static_cast<MeshFileReads*>(ctx);
  try {
    const std::vector<uint8_t>& b = reads->load(file);
    *data = b.data(), *size = b.size();
    return true;
  } catch (const Error& e) {
    if (reads->error.empty()) reads->error = e.what();
  } catch (...) {}
  return false;
}

}  // namespace

const std::vector<uint8_t>& MeshFileReads::load(const std::string& file) {
  auto it = files_.find(file);
  if (it == files_.end()) it = files_.emplace(file, read_input_bytes(file, InputKind::kMesh)).first;
  return it->second;
}

ImportedScene import_mesh_file(const std::string& path, unsigned flags, MeshFileReads* reads) {
  MeshFileReads local;
  MeshFileReads* io = reads ? reads : &local;
  const std::vector<uint8_t>& bytes = io->load(path);
  // Node depth, buffer sizes, accessor counts: refused before Assimp recurses through them (issue 26),
  // from the bytes Assimp will parse.
  check_gltf_bytes(path, bytes, [io](const std::string& f) -> int64_t {
    try {
      return int64_t(io->load(f).size());
    } catch (const Error&) {
      return -1;
    }
  });
  const AssimpModule& assimp = assimp_module(path);
  AssimpFiles files;
  files.ctx = io, files.exists = assimp_file_exists, files.read = assimp_file_read;
  ImportedScene scene;
  bool dropped_faces = false;
  std::string err;
  const bool ok = assimp.import(path, flags, files, &scene, &dropped_faces, &err);
  if (dropped_faces) throw file_error(path, "a vertex index is out of range (faces using it would be dropped)");
  if (!ok) {
    if (!io->error.empty()) throw Error(io->error);
    throw file_error(path, "cannot read mesh (" + one_line(err) + ")");
  }
  return scene;
}

MeshTriangles read_mesh_lightmap(const std::string& path, int uv_set, MeshReadInfo* info) {
  if (!input_exists(path)) throw file_error(path, "file not found");
  std::string ext = utf8_string(fs_path(path).extension());
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  // Only formats whose UV origin we know (the v-flip rule depends on it).
  if (ext != ".gltf" && ext != ".glb" && ext != ".obj")
    throw file_error(path, "unsupported mesh format '" + ext + "' (.gltf, .glb, .obj)");
  if (uv_set < -1) throw file_error(path, "UV set must be ≥ 0");

  // No aiProcess_FlipUVs: Assimp already stores glTF's v as 1 − v, so both formats arrive v-up.
  // PreTransformVertices bakes node matrices into the vertices (normals by the inverse transpose).
  const ImportedScene scene =
      import_mesh_file(path, kImportTriangulate | kImportPreTransformVertices | kImportValidateDataStructure);

  // The scene's UV sets: the fewest and most any triangle mesh has.
  int fewest = int(kImportedUvSets) + 1, most = 0, meshes = 0;
  bool any_normals = false;
  for (unsigned m = 0; m < scene.meshes.size(); ++m) {
    const ImportedMesh& mesh = scene.meshes[m];
    if (!has_triangles(mesh)) continue;
    ++meshes;
    const int sets = int(mesh.uv_sets);
    if (sets == 0) throw file_error(path, "mesh " + mesh_name(mesh, m) + " has no UVs (texture coordinates)");
    fewest = std::min(fewest, sets);
    most = std::max(most, sets);
    any_normals = any_normals || !mesh.normals.empty();
  }
  if (meshes == 0) throw file_error(path, "no triangles");
  int set = uv_set;
  if (set < 0) {
    if (fewest < 2 && most >= 2)
      throw file_error(path, "meshes have between " + std::to_string(fewest) + " and " + std::to_string(most) +
                                 " UV sets: say which holds the lightmap UVs (--uv-set)");
    set = fewest >= 2 ? 1 : 0;
  }

  MeshTriangles out;
  for (unsigned m = 0; m < scene.meshes.size(); ++m) {
    const ImportedMesh& mesh = scene.meshes[m];
    if (!has_triangles(mesh)) continue;
    const int sets = int(mesh.uv_sets);
    if (set >= sets)
      throw file_error(path, "UV set " + std::to_string(set) + " requested, mesh " + mesh_name(mesh, m) + " has " +
                                 std::to_string(sets) + (sets == 1 ? " UV set" : " UV sets") + " (0.." +
                                 std::to_string(sets - 1) + ")");
    const size_t base = out.positions.size() / 3;
    if (base + mesh.vertices > size_t(UINT32_MAX)) throw file_error(path, "more than 2^32 vertices");
    const float* uv = mesh.uv[size_t(set)].data();
    const bool has_normals = !mesh.normals.empty();
    for (unsigned v = 0; v < mesh.vertices; ++v) {
      const float* p = &mesh.positions[size_t(v) * 3];
      out.positions.insert(out.positions.end(), {p[0], p[1], p[2]});
      out.uv.insert(out.uv.end(), {uv[size_t(v) * 2], uv[size_t(v) * 2 + 1]});
      if (any_normals) {
        const float* n = has_normals ? &mesh.normals[size_t(v) * 3] : nullptr;
        out.normals.insert(out.normals.end(), {n ? n[0] : 0.0f, n ? n[1] : 0.0f, n ? n[2] : 0.0f});
      }
    }
    for (size_t f = 0; f < mesh.faces(); ++f) {
      if (mesh.face_size(f) != 3) continue;  // points and lines cover no area
      const uint32_t* face = mesh.face(f);
      for (unsigned k = 0; k < 3; ++k) {
        if (face[k] >= mesh.vertices)
          throw file_error(path, "mesh " + mesh_name(mesh, m) + ": vertex index " + std::to_string(face[k]) +
                                     " out of range (" + std::to_string(mesh.vertices) + " vertices)");
        out.indices.push_back(uint32_t(base + face[k]));
      }
    }
  }
  if (out.indices.empty()) throw file_error(path, "no triangles");
  if (info) *info = {set, fewest, meshes, out.indices.size() / 3};
  return out;
}

}  // namespace ahd
