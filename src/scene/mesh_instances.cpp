// read_mesh_instances (scene/mesh_io.h): the scene's nodes kept apart for atlas placement.
#include <cmath>

#include "core/error.h"
#include "scene/assimp_math.h"
#include "scene/mesh_io.h"

namespace ahd {

namespace {

struct Walk {
  const ImportedScene* scene;
  int set;
  MeshInstances* out;
  const std::string* path;
};

void add_node(const Walk& w, const ImportedNode& node, const Mat4f& parent) {
  const Mat4f m = mat4_mul(parent, node.transform);
  if (!node.meshes.empty()) {
    MeshTriangles& t = w.out->mesh;
    MeshInstance inst;
    inst.node = node.name;
    inst.first_vertex = t.positions.size() / 3;
    inst.first_index = t.indices.size();
    const Mat3f nm = mat3_inverse_transpose(mat3_of(m));  // normals: inverse transpose of the linear part
    for (unsigned k : node.meshes) {
      const ImportedMesh& mesh = w.scene->meshes[k];
      if (!(mesh.primitive_types & kPrimitiveTriangle)) continue;
      // The merged read checked the file; this second read must see the same one.
      if (unsigned(w.set) >= mesh.uv_sets) throw file_error(*w.path, "changed while it was read (a UV set is gone)");
      inst.meshes.push_back(mesh.name);
      const size_t base = t.positions.size() / 3;
      // Each node is a copy of its meshes: the copies are bounded in all, not by the file's size.
      if (base + mesh.vertices > kMaxSceneVertices || t.indices.size() + mesh.faces() * 3 > kMaxSceneIndices)
        throw file_error(*w.path, "its nodes instance more than " + std::to_string(kMaxSceneVertices) + " vertices or " +
                                      std::to_string(kMaxSceneIndices) + " indices in all (docs/robustness-input.md)");
      const bool has_normals = !mesh.normals.empty();
      for (unsigned v = 0; v < mesh.vertices; ++v) {
        const float* q = &mesh.positions[size_t(v) * 3];
        const Vec3f p = mat4_point(m, {q[0], q[1], q[2]});
        t.positions.insert(t.positions.end(), {p.x, p.y, p.z});
        const float* uv = &mesh.uv[size_t(w.set)][size_t(v) * 2];
        t.uv.insert(t.uv.end(), {uv[0], uv[1]});
        Vec3f n;
        if (has_normals) {
          const float* r = &mesh.normals[size_t(v) * 3];
          n = mat3_mul(nm, {r[0], r[1], r[2]});
          const float len = vec3_length(n);
          if (len > 0 && std::isfinite(len)) vec3_div(&n, len);
        }
        t.normals.insert(t.normals.end(), {n.x, n.y, n.z});
      }
      for (size_t f = 0; f < mesh.faces(); ++f)
        if (mesh.face_size(f) == 3)
          for (unsigned c = 0; c < 3; ++c) {
            if (mesh.face(f)[c] >= mesh.vertices)
              throw file_error(*w.path, "changed while it was read (a vertex index is out of range)");
            t.indices.push_back(uint32_t(base + mesh.face(f)[c]));
          }
    }
    inst.vertices = t.positions.size() / 3 - inst.first_vertex;
    inst.indices = t.indices.size() - inst.first_index;
    if (inst.indices) w.out->instances.push_back(inst);
  }
  for (unsigned c : node.children) add_node(w, w.scene->nodes[c], m);
}

}  // namespace

MeshInstances read_mesh_instances(const std::string& path, int uv_set, MeshReadInfo* info) {
  // The merged read validates the file, its UV sets and indices and picks the set.
  MeshReadInfo mi;
  read_mesh_lightmap(path, uv_set, &mi);
  const ImportedScene scene = import_mesh_file(path, kImportTriangulate | kImportValidateDataStructure);
  MeshInstances out;
  add_node({&scene, mi.uv_set, &out, &path}, scene.nodes[0], kMat4fIdentity);
  bool any_normals = false;
  for (const ImportedMesh& m : scene.meshes) any_normals = any_normals || !m.normals.empty();
  if (!any_normals) out.mesh.normals.clear();
  if (info) *info = mi, info->triangles = out.mesh.indices.size() / 3;
  return out;
}

}  // namespace ahd
