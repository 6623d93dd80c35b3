// read_mesh_instances (scene/mesh_io.h): the scene's nodes kept apart for atlas placement.
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <cmath>

#include "core/error.h"
#include "scene/mesh_io.h"

namespace ahd {

namespace {

struct Walk {
  const aiScene* scene;
  int set;
  MeshInstances* out;
  const std::string* path;
};

void add_node(const Walk& w, const aiNode* node, const aiMatrix4x4& parent) {
  const aiMatrix4x4 m = parent * node->mTransformation;
  if (node->mNumMeshes > 0) {
    MeshTriangles& t = w.out->mesh;
    MeshInstance inst;
    inst.node = node->mName.C_Str();
    inst.first_vertex = t.positions.size() / 3;
    inst.first_index = t.indices.size();
    aiMatrix3x3 nm(m);  // normals: inverse transpose of the linear part
    nm.Inverse().Transpose();
    for (unsigned k = 0; k < node->mNumMeshes; ++k) {
      const aiMesh* mesh = w.scene->mMeshes[node->mMeshes[k]];
      if (!(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
      // The merged read checked the file; this second read must see the same one.
      if (!mesh->mTextureCoords[w.set]) throw file_error(*w.path, "changed while it was read (a UV set is gone)");
      inst.meshes.push_back(mesh->mName.C_Str());
      const size_t base = t.positions.size() / 3;
      // Each node is a copy of its meshes: the copies are bounded in all, not by the file's size.
      if (base + mesh->mNumVertices > kMaxSceneVertices || t.indices.size() + size_t(mesh->mNumFaces) * 3 > kMaxSceneIndices)
        throw file_error(*w.path, "its nodes instance more than " + std::to_string(kMaxSceneVertices) + " vertices or " +
                                      std::to_string(kMaxSceneIndices) + " indices in all (docs/robustness-input.md)");
      for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
        const aiVector3D p = m * mesh->mVertices[v];
        t.positions.insert(t.positions.end(), {p.x, p.y, p.z});
        const aiVector3D& uv = mesh->mTextureCoords[w.set][v];
        t.uv.insert(t.uv.end(), {uv.x, uv.y});
        aiVector3D n(0, 0, 0);
        if (mesh->HasNormals()) {
          n = nm * mesh->mNormals[v];
          const float len = n.Length();
          if (len > 0 && std::isfinite(len)) n /= len;
        }
        t.normals.insert(t.normals.end(), {n.x, n.y, n.z});
      }
      for (unsigned f = 0; f < mesh->mNumFaces; ++f)
        if (mesh->mFaces[f].mNumIndices == 3)
          for (unsigned c = 0; c < 3; ++c) {
            if (mesh->mFaces[f].mIndices[c] >= mesh->mNumVertices)
              throw file_error(*w.path, "changed while it was read (a vertex index is out of range)");
            t.indices.push_back(uint32_t(base + mesh->mFaces[f].mIndices[c]));
          }
    }
    inst.vertices = t.positions.size() / 3 - inst.first_vertex;
    inst.indices = t.indices.size() - inst.first_index;
    if (inst.indices) w.out->instances.push_back(inst);
  }
  for (unsigned c = 0; c < node->mNumChildren; ++c) add_node(w, node->mChildren[c], m);
}

}  // namespace

MeshInstances read_mesh_instances(const std::string& path, int uv_set, MeshReadInfo* info) {
  // The merged read validates the file, its UV sets and indices and picks the set.
  MeshReadInfo mi;
  read_mesh_lightmap(path, uv_set, &mi);
  Assimp::Importer importer;
  const aiScene* scene = import_mesh_file(&importer, path, aiProcess_Triangulate | aiProcess_ValidateDataStructure);
  MeshInstances out;
  add_node({scene, mi.uv_set, &out, &path}, scene->mRootNode, aiMatrix4x4());
  bool any_normals = false;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) any_normals = any_normals || scene->mMeshes[m]->HasNormals();
  if (!any_normals) out.mesh.normals.clear();
  if (info) *info = mi, info->triangles = out.mesh.indices.size() / 3;
  return out;
}

}  // namespace ahd
