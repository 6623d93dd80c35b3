#include "bakers/scene_export.h"

#include <cmath>
#include <map>

#include "bakers/godot/godot_scene.h"
#include "core/error.h"
#include "scene/gltf_write.h"
#include "scene/mesh_io.h"
#include "scene/placement_io.h"

namespace ahd {

namespace {

// Placement keeps MeshTriangles' v-up convention (scene/placement.h): atlas_v = v · sy + oy. In
// glTF's (v' = 1 − v): atlas_v' = v' · sy + (1 − sy − oy).
ManifestInstance to_instance(const Placement& p) {
  ManifestInstance m;
  m.node = p.node;
  m.page = p.page;
  m.scale[0] = p.scale[0], m.scale[1] = p.scale[1];
  m.offset[0] = p.offset[0], m.offset[1] = 1.0 - p.scale[1] - p.offset[1];
  return m;
}

// The scene's instances and their placements, or false when the input has none.
bool placed_scene(const BakeInput& a, MeshInstances* scene, std::vector<Placement>* placements) {
  if (a.godot) {
    *scene = a.godot->scene, *placements = a.godot->placements;
    return true;
  }
  if (a.scene.empty() && !a.mesh.empty() && !a.placement.empty()) {
    *scene = read_mesh_instances(a.mesh, a.uv_set);
    *placements = read_placements(a.placement);
    return true;
  }
  return false;
}

// Unit vertex normals: the mesh's, or (none, or a zero one) the area-weighted face normals around it.
std::vector<float> vertex_normals(const MeshTriangles& m, const MeshInstance& in) {
  std::vector<float> n(in.vertices * 3, 0.0f);
  const bool has = m.normals.size() == m.positions.size();
  if (has)
    for (size_t v = 0; v < in.vertices * 3; ++v) n[v] = m.normals[in.first_vertex * 3 + v];
  std::vector<double> face(in.vertices * 3, 0.0);
  for (size_t t = in.first_index; t + 2 < in.first_index + in.indices; t += 3) {
    const uint32_t i[3] = {m.indices[t], m.indices[t + 1], m.indices[t + 2]};
    double e1[3], e2[3];
    for (int c = 0; c < 3; ++c)
      e1[c] = double(m.positions[i[1] * 3 + c]) - m.positions[i[0] * 3 + c],
      e2[c] = double(m.positions[i[2] * 3 + c]) - m.positions[i[0] * 3 + c];
    const double f[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    for (uint32_t k : i)
      for (int c = 0; c < 3; ++c) face[(k - in.first_vertex) * 3 + c] += f[c];
  }
  for (size_t v = 0; v < in.vertices; ++v) {
    float* p = &n[v * 3];
    double len = std::sqrt(double(p[0]) * p[0] + double(p[1]) * p[1] + double(p[2]) * p[2]);
    if (len > 1e-12) continue;
    len = std::sqrt(face[v * 3] * face[v * 3] + face[v * 3 + 1] * face[v * 3 + 1] + face[v * 3 + 2] * face[v * 3 + 2]);
    for (int c = 0; c < 3; ++c) p[c] = len > 0 ? float(face[v * 3 + size_t(c)] / len) : (c == 2 ? 1.0f : 0.0f);
  }
  return n;
}

}  // namespace

std::vector<ManifestInstance> bake_instances(const BakeInput& a) {
  std::vector<ManifestInstance> out;
  if (a.godot) {
    for (const Placement& p : a.godot->placements) out.push_back(to_instance(p));
  } else if (a.scene.empty() && !a.mesh.empty() && !a.placement.empty()) {
    for (const Placement& p : read_placements(a.placement)) out.push_back(to_instance(p));
  }
  return out;
}

PlacedSceneMesh bake_placed_mesh(const BakeInput& a) {
  PlacedSceneMesh out;
  MeshInstances scene;
  std::vector<Placement> placements;
  if (!placed_scene(a, &scene, &placements)) return out;
  std::map<std::string, size_t> by_node;
  for (size_t i = 0; i < scene.instances.size(); ++i) by_node.emplace(scene.instances[i].node, i);
  const MeshTriangles& m = scene.mesh;
  for (const Placement& p : placements) {
    const auto it = by_node.find(p.node);
    if (it == by_node.end()) continue;  // place_instances refused such a placement while reading
    const MeshInstance& in = scene.instances[it->second];
    const uint32_t base = uint32_t(out.mesh.positions.size() / 3);
    out.mesh.positions.insert(out.mesh.positions.end(), m.positions.begin() + long(in.first_vertex * 3),
                              m.positions.begin() + long((in.first_vertex + in.vertices) * 3));
    for (size_t v = 0; v < in.vertices; ++v)  // Placement's own convention (v up): atlas = uv · scale + offset
      for (int c = 0; c < 2; ++c)
        out.mesh.uv.push_back(float(double(m.uv[(in.first_vertex + v) * 2 + size_t(c)]) * p.scale[c] + p.offset[c]));
    for (size_t t = 0; t < in.indices; ++t)
      out.mesh.indices.push_back(base + uint32_t(m.indices[in.first_index + t] - in.first_vertex));
    out.triangle_page.insert(out.triangle_page.end(), in.indices / 3, int32_t(p.page));
    ++out.instances;
  }
  return out;
}

SceneGltf bake_scene_gltf(const BakeInput& a) {
  MeshInstances scene;
  std::vector<Placement> placements;
  if (!placed_scene(a, &scene, &placements))
    throw Error((a.input.empty() ? std::string("the sample") : a.input) +
                ": no placed scene (a Godot project's scene, or --mesh with --placement) to write");
  std::map<std::string, size_t> by_node;
  for (size_t i = 0; i < scene.instances.size(); ++i) by_node.emplace(scene.instances[i].node, i);
  SceneGltf out;
  std::vector<GltfInstanceMesh> meshes;
  const MeshTriangles& m = scene.mesh;
  for (const Placement& p : placements) {
    const auto it = by_node.find(p.node);
    if (it == by_node.end()) continue;  // place_instances refused such a placement while reading
    const MeshInstance& in = scene.instances[it->second];
    const ManifestInstance mi = to_instance(p);
    GltfInstanceMesh g;
    g.name = p.node;
    g.positions.assign(m.positions.begin() + long(in.first_vertex * 3), m.positions.begin() + long((in.first_vertex + in.vertices) * 3));
    g.normals = vertex_normals(m, in);
    for (size_t v = 0; v < in.vertices; ++v) {
      const double u = m.uv[(in.first_vertex + v) * 2], w = 1.0 - double(m.uv[(in.first_vertex + v) * 2 + 1]);
      g.uv0.push_back(float(u)), g.uv0.push_back(float(w));
      g.uv1.push_back(float(u * mi.scale[0] + mi.offset[0])), g.uv1.push_back(float(w * mi.scale[1] + mi.offset[1]));
    }
    for (size_t t = 0; t < in.indices; ++t) g.indices.push_back(uint32_t(m.indices[in.first_index + t] - in.first_vertex));
    g.extras = {{"ahd_page", p.page},
                {"ahd_uv_scale", {mi.scale[0], mi.scale[1]}},
                {"ahd_uv_offset", {mi.offset[0], mi.offset[1]}}};
    out.pages = std::max(out.pages, p.page + 1);
    out.triangles += in.indices / 3;
    meshes.push_back(std::move(g));
  }
  out.instances = meshes.size();
  if (meshes.empty()) throw Error((a.input.empty() ? std::string("the sample") : a.input) + ": no placed instance to write");
  const nlohmann::json extras = {
      {"ahd_lightmap_uv", "TEXCOORD_1: atlas space, glTF convention (v down); sample the planes' layer ahd_page"}};
  out.glb = write_glb(meshes, extras, "ahdpack scene");
  return out;
}

}  // namespace ahd
