#include "scene/mesh_io.h"

#include <algorithm>
#include <assimp/DefaultLogger.hpp>
#include <assimp/IOSystem.hpp>
#include <assimp/MemoryIOWrapper.h>
#include <assimp/Importer.hpp>
#include <assimp/LogStream.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
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

std::string mesh_name(const aiMesh* m, unsigned index) {
  return m->mName.length ? "'" + std::string(m->mName.C_Str()) + "'" : "#" + std::to_string(index);
}

// Assimp's glTF importer drops faces whose indices are out of range with only a warning; OBJ's
// are an error. This stream catches that warning so both formats refuse such a file.
struct DroppedFacesStream : Assimp::LogStream {
  bool dropped = false;
  void write(const char* message) override {
    if (std::strstr(message, "out-of-range indices")) dropped = true;
  }
};

// Assimp's logger is process-wide: every import holds this lock while it creates, uses and
// destroys it (an import without the lock could log into a logger another thread just killed).
std::mutex g_assimp_mutex;

bool has_triangles(const aiMesh* m) { return (m->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) != 0; }

// Assimp's file system over the opener (files/input_file.h): each file it opens (the mesh, a
// .gltf's .bin buffers, an .obj's .mtl) read once into memory, bounded, regular files only, noted
// in the input record; Assimp parses those bytes.
class BufferedIOSystem : public Assimp::IOSystem {
 public:
  // The bytes of `file`, read on first use. Throws ahd::Error.
  const std::vector<uint8_t>& load(const std::string& file) {
    auto it = files_.find(file);
    if (it == files_.end()) it = files_.emplace(file, read_input_bytes(file, InputKind::kMesh)).first;
    return it->second;
  }
  bool Exists(const char* file) const override {
    if (!file) return false;
    if (files_.count(file)) return true;
    std::error_code ec;
    return fs::is_regular_file(fs_path(file), ec);
  }
  char getOsSeparator() const override { return '/'; }
  Assimp::IOStream* Open(const char* file, const char* mode) override {
    if (!file || !mode || std::strchr(mode, 'w') || std::strchr(mode, 'a')) return nullptr;
    try {
      const std::vector<uint8_t>& b = load(file);
      return new Assimp::MemoryIOStream(b.data(), b.size(), false);
    } catch (const Error& e) {
      if (error.empty()) error = e.what();
      return nullptr;
    }
  }
  void Close(Assimp::IOStream* stream) override { delete stream; }
  std::string error;  // the first file that could not be read, for the message

 private:
  std::map<std::string, std::vector<uint8_t>> files_;
};

}  // namespace

void record_assimp_reads(Assimp::Importer* importer) { importer->SetIOHandler(new BufferedIOSystem); }

const std::vector<uint8_t>& imported_file_bytes(Assimp::Importer* importer, const std::string& path) {
  auto* io = dynamic_cast<BufferedIOSystem*>(importer->GetIOHandler());
  if (!io) throw file_error(path, "not imported through import_mesh_file");
  return io->load(path);
}

const aiScene* import_mesh_file(Assimp::Importer* importer, const std::string& path, unsigned flags) {
  auto* io = new BufferedIOSystem;
  importer->SetIOHandler(io);  // owned by the importer
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
  const aiScene* scene = nullptr;
  bool dropped_faces = false;
  {
    std::lock_guard<std::mutex> lock(g_assimp_mutex);
    Assimp::DefaultLogger::create("", Assimp::Logger::NORMAL, 0);
    auto* stream = new DroppedFacesStream;  // owned by the logger once attached
    Assimp::DefaultLogger::get()->attachStream(stream, Assimp::Logger::Warn | Assimp::Logger::Err);
    scene = importer->ReadFile(path, flags);
    dropped_faces = stream->dropped;
    Assimp::DefaultLogger::kill();
  }
  if (dropped_faces) throw file_error(path, "a vertex index is out of range (faces using it would be dropped)");
  if (!scene || !scene->mRootNode) {
    if (!io->error.empty()) throw Error(io->error);
    throw file_error(path, "cannot read mesh (" + one_line(importer->GetErrorString()) + ")");
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

  Assimp::Importer importer;
  // No aiProcess_FlipUVs: Assimp already stores glTF's v as 1 − v, so both formats arrive v-up.
  // PreTransformVertices bakes node matrices into the vertices (normals by the inverse transpose).
  const aiScene* scene = import_mesh_file(
      &importer, path, aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_ValidateDataStructure);

  // The scene's UV sets: the fewest and most any triangle mesh has.
  int fewest = AI_MAX_NUMBER_OF_TEXTURECOORDS + 1, most = 0, meshes = 0;
  bool any_normals = false;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    if (!has_triangles(mesh)) continue;
    ++meshes;
    const int sets = int(mesh->GetNumUVChannels());
    if (sets == 0) throw file_error(path, "mesh " + mesh_name(mesh, m) + " has no UVs (texture coordinates)");
    fewest = std::min(fewest, sets);
    most = std::max(most, sets);
    any_normals = any_normals || mesh->HasNormals();
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
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    if (!has_triangles(mesh)) continue;
    const int sets = int(mesh->GetNumUVChannels());
    if (set >= sets)
      throw file_error(path, "UV set " + std::to_string(set) + " requested, mesh " + mesh_name(mesh, m) + " has " +
                                 std::to_string(sets) + (sets == 1 ? " UV set" : " UV sets") + " (0.." +
                                 std::to_string(sets - 1) + ")");
    const size_t base = out.positions.size() / 3;
    if (base + mesh->mNumVertices > size_t(UINT32_MAX)) throw file_error(path, "more than 2^32 vertices");
    const aiVector3D* uv = mesh->mTextureCoords[set];
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D& p = mesh->mVertices[v];
      out.positions.insert(out.positions.end(), {p.x, p.y, p.z});
      out.uv.insert(out.uv.end(), {uv[v].x, uv[v].y});
      if (any_normals) {
        const aiVector3D n = mesh->HasNormals() ? mesh->mNormals[v] : aiVector3D(0, 0, 0);
        out.normals.insert(out.normals.end(), {n.x, n.y, n.z});
      }
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines cover no area
      for (unsigned k = 0; k < 3; ++k) {
        if (face.mIndices[k] >= mesh->mNumVertices)
          throw file_error(path, "mesh " + mesh_name(mesh, m) + ": vertex index " + std::to_string(face.mIndices[k]) +
                                     " out of range (" + std::to_string(mesh->mNumVertices) + " vertices)");
        out.indices.push_back(uint32_t(base + face.mIndices[k]));
      }
    }
  }
  if (out.indices.empty()) throw file_error(path, "no triangles");
  if (info) *info = {set, fewest, meshes, out.indices.size() / 3};
  return out;
}

}  // namespace ahd
