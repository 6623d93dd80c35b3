// libahd_assimp.so: Assimp's import for ahdpack, loaded with dlopen only when a mesh is read
// (src/scene/assimp_module.h). Assimp parses the files the caller hands over and its scene is copied
// into plain data; no ahdpack state here: the opener, the checks and the messages stay in the process.
// Built with AHD_ASSIMP_MODULE=OFF (AHD_ASSIMP_BUILTIN) this is compiled into ahdpack itself.
#include <assimp/DefaultLogger.hpp>
#include <assimp/IOSystem.hpp>
#include <assimp/Importer.hpp>
#include <assimp/LogStream.hpp>
#include <assimp/MemoryIOWrapper.h>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <cstring>
#include <exception>
#include <mutex>
#include <set>
#include <utility>

#include "scene/assimp_module.h"

namespace {

using ahd::AssimpFiles;
using ahd::ImportedMesh;
using ahd::ImportedNode;
using ahd::ImportedScene;

// Assimp's glTF importer drops faces whose indices are out of range with only a warning; OBJ's
// are an error. This stream catches that warning so the caller refuses both alike.
struct DroppedFacesStream : Assimp::LogStream {
  bool dropped = false;
  void write(const char* message) override {
    if (std::strstr(message, "out-of-range indices")) dropped = true;
  }
};

// Assimp's logger is process-wide: every import holds this lock while it creates, uses and
// destroys it (an import without the lock could log into a logger another thread just killed).
std::mutex g_assimp_mutex;

// Assimp's file system over the caller's files (each read once, in memory, by the caller).
class CallbackIOSystem : public Assimp::IOSystem {
 public:
  explicit CallbackIOSystem(const AssimpFiles& files) : files_(files) {}
  bool Exists(const char* file) const override { return file && files_.exists(files_.ctx, file); }
  char getOsSeparator() const override { return '/'; }
  Assimp::IOStream* Open(const char* file, const char* mode) override {
    if (!file || !mode || std::strchr(mode, 'w') || std::strchr(mode, 'a')) return nullptr;
    const uint8_t* data = nullptr;
    size_t size = 0;
    if (!files_.read(files_.ctx, file, &data, &size)) return nullptr;
    return new Assimp::MemoryIOStream(data, size, false);
  }
  void Close(Assimp::IOStream* stream) override { delete stream; }

 private:
  const AssimpFiles& files_;
};

void put3(const aiVector3D* v, unsigned n, std::vector<float>* out) {
  if (!v || n == 0) return;
  out->resize(size_t(n) * 3);
  for (unsigned i = 0; i < n; ++i) {
    float* o = &(*out)[size_t(i) * 3];
    o[0] = v[i].x, o[1] = v[i].y, o[2] = v[i].z;
  }
}

void copy_mesh(const aiMesh* m, ImportedMesh* out) {
  out->name = m->mName.C_Str();
  out->primitive_types = m->mPrimitiveTypes;
  out->vertices = m->mNumVertices;
  const unsigned n = m->mNumVertices;
  put3(m->mVertices, n, &out->positions);
  put3(m->mNormals, n, &out->normals);
  if (m->HasTangentsAndBitangents()) put3(m->mTangents, n, &out->tangents), put3(m->mBitangents, n, &out->bitangents);
  for (unsigned k = 0; k < ahd::kImportedUvSets && k < AI_MAX_NUMBER_OF_TEXTURECOORDS; ++k) {
    if (!m->HasTextureCoords(k)) continue;
    std::vector<float>& uv = out->uv[k];
    uv.resize(size_t(n) * 2);
    for (unsigned i = 0; i < n; ++i) {
      const aiVector3D& t = m->mTextureCoords[k][i];
      uv[size_t(i) * 2] = t.x, uv[size_t(i) * 2 + 1] = t.y;
    }
  }
  out->uv_sets = m->GetNumUVChannels();
  if (m->HasVertexColors(0)) {
    out->colors.resize(size_t(n) * 4);
    for (unsigned i = 0; i < n; ++i) {
      const aiColor4D& c = m->mColors[0][i];
      float* o = &out->colors[size_t(i) * 4];
      o[0] = c.r, o[1] = c.g, o[2] = c.b, o[3] = c.a;
    }
  }
  out->face_first.reserve(size_t(m->mNumFaces) + 1);
  out->face_first.push_back(0);
  for (unsigned f = 0; f < m->mNumFaces; ++f) {
    const aiFace& face = m->mFaces[f];
    if (face.mNumIndices) out->indices.insert(out->indices.end(), face.mIndices, face.mIndices + face.mNumIndices);
    out->face_first.push_back(uint32_t(out->indices.size()));
  }
}

void copy_scene(const aiScene* sc, ImportedScene* out) {
  out->meshes.resize(sc->mNumMeshes);
  for (unsigned m = 0; m < sc->mNumMeshes; ++m) copy_mesh(sc->mMeshes[m], &out->meshes[m]);
  // Nodes breadth first (no recursion: a file's depth is the caller's check, not the stack's).
  std::vector<const aiNode*> todo = {sc->mRootNode};
  out->nodes.emplace_back();
  for (size_t i = 0; i < todo.size(); ++i) {
    const aiNode* an = todo[i];
    ImportedNode& n = out->nodes[i];
    n.name = an->mName.C_Str();
    const aiMatrix4x4& t = an->mTransformation;
    n.transform = {t.a1, t.a2, t.a3, t.a4, t.b1, t.b2, t.b3, t.b4, t.c1, t.c2, t.c3, t.c4, t.d1, t.d2, t.d3, t.d4};
    if (an->mNumMeshes) n.meshes.assign(an->mMeshes, an->mMeshes + an->mNumMeshes);
    for (unsigned c = 0; c < an->mNumChildren; ++c) {
      out->nodes[i].children.push_back(unsigned(todo.size()));
      todo.push_back(an->mChildren[c]);
      out->nodes.emplace_back();
      out->nodes.back().parent = int(i);
    }
  }
  if (const aiMetadata* md = sc->mMetaData) {
    std::set<std::string> seen;  // aiMetadata::Get looks at a key's first entry only
    for (unsigned k = 0; k < md->mNumProperties; ++k) {
      const std::string key(md->mKeys[k].data, md->mKeys[k].length);
      if (!seen.insert(key).second || !md->mValues[k].mData) continue;
      const void* d = md->mValues[k].mData;
      switch (md->mValues[k].mType) {
        case AI_INT32:
          out->meta_int32.emplace(key, *static_cast<const int32_t*>(d));
          break;
        case AI_FLOAT:
          out->meta_float.emplace(key, *static_cast<const float*>(d));
          break;
        case AI_DOUBLE:
          out->meta_double.emplace(key, *static_cast<const double*>(d));
          break;
        default:
          break;
      }
    }
  }
}

unsigned assimp_flags(unsigned flags) {
  unsigned f = 0;
  if (flags & ahd::kImportTriangulate) f |= aiProcess_Triangulate;
  if (flags & ahd::kImportPreTransformVertices) f |= aiProcess_PreTransformVertices;
  if (flags & ahd::kImportValidateDataStructure) f |= aiProcess_ValidateDataStructure;
  return f;
}

bool import_file(const std::string& path, unsigned flags, const AssimpFiles& files, ImportedScene* out,
                 bool* dropped_faces, std::string* err) {
  *dropped_faces = false;
  try {
    Assimp::Importer importer;
    importer.SetIOHandler(new CallbackIOSystem(files));  // owned by the importer
    if (flags & ahd::kImportFbxNoPivots) importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS, false);
    const aiScene* scene = nullptr;
    {
      std::lock_guard<std::mutex> lock(g_assimp_mutex);
      Assimp::DefaultLogger::create("", Assimp::Logger::NORMAL, 0);
      auto* stream = new DroppedFacesStream;  // owned by the logger once attached
      Assimp::DefaultLogger::get()->attachStream(stream, Assimp::Logger::Warn | Assimp::Logger::Err);
      try {
        scene = importer.ReadFile(path, assimp_flags(flags));
      } catch (...) {
        Assimp::DefaultLogger::kill();
        throw;
      }
      *dropped_faces = stream->dropped;
      Assimp::DefaultLogger::kill();
    }
    if (!scene || !scene->mRootNode) {
      *err = importer.GetErrorString();
      return false;
    }
    copy_scene(scene, out);
    return true;
  } catch (const std::exception& e) {
    *err = e.what();
  } catch (...) {
    *err = "unknown error";
  }
  *out = ImportedScene();
  return false;
}

const ahd::AssimpModule kModule = {ahd::kAssimpModuleAbi, import_file};

}  // namespace

// The module's one exported symbol (GetProcAddress finds only exported names on Windows). Built
// into ahdpack (AHD_ASSIMP_BUILTIN) it is an ordinary function the loader calls.
#if defined(AHD_ASSIMP_BUILTIN)
#define AHD_ASSIMP_EXPORT
#elif defined(_WIN32)
#define AHD_ASSIMP_EXPORT __declspec(dllexport)
#else
#define AHD_ASSIMP_EXPORT __attribute__((visibility("default")))
#endif
extern "C" AHD_ASSIMP_EXPORT const void* ahd_assimp_module() { return &kModule; }
