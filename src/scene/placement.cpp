#include "scene/placement.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "core/error.h"

namespace ahd {

namespace {

struct Rect {
  double x0, y0, x1, y1;
};

Rect uv_bounds(const MeshTriangles& m, size_t first_vertex, size_t vertices) {
  Rect r{1e300, 1e300, -1e300, -1e300};
  for (size_t v = first_vertex; v < first_vertex + vertices; ++v) {
    r.x0 = std::min(r.x0, double(m.uv[v * 2])), r.x1 = std::max(r.x1, double(m.uv[v * 2]));
    r.y0 = std::min(r.y0, double(m.uv[v * 2 + 1])), r.y1 = std::max(r.y1, double(m.uv[v * 2 + 1]));
  }
  return r;
}

bool overlap(const Rect& a, const Rect& b) {
  return std::min(a.x1, b.x1) > std::max(a.x0, b.x0) && std::min(a.y1, b.y1) > std::max(a.y0, b.y0);
}

}  // namespace

PlacedMesh place_instances(const MeshInstances& scene, const std::vector<Placement>& placements, int page,
                           const std::string& source) {
  std::map<std::string, const Placement*> by_node;
  for (const Placement& p : placements) {
    for (int a = 0; a < 2; ++a)
      if (!(p.scale[a] > 0 && std::isfinite(p.scale[a]) && std::isfinite(p.offset[a])))
        throw file_error(source, "placement of '" + p.node + "' needs a finite positive scale and a finite offset");
    by_node[p.node] = &p;
  }
  std::set<std::string> nodes;  // looked up once each, not placements × instances
  for (const MeshInstance& i : scene.instances) nodes.insert(i.node);
  for (const Placement& p : placements)
    if (!nodes.count(p.node)) throw file_error(source, "places '" + p.node + "', which is no mesh instance (node) of the scene");
  PlacedMesh out;
  const MeshTriangles& m = scene.mesh;
  const bool normals = !m.normals.empty();
  std::vector<Rect> rects;
  for (const MeshInstance& inst : scene.instances) {
    const auto it = by_node.find(inst.node);
    if (it == by_node.end()) {
      out.unplaced.push_back(inst.node);
      continue;
    }
    const Placement& p = *it->second;
    if (p.page != page) continue;
    const size_t base = out.mesh.positions.size() / 3;
    for (size_t v = inst.first_vertex; v < inst.first_vertex + inst.vertices; ++v) {
      out.mesh.positions.insert(out.mesh.positions.end(), m.positions.begin() + std::ptrdiff_t(v * 3),
                                m.positions.begin() + std::ptrdiff_t(v * 3 + 3));
      if (normals)
        out.mesh.normals.insert(out.mesh.normals.end(), m.normals.begin() + std::ptrdiff_t(v * 3),
                                m.normals.begin() + std::ptrdiff_t(v * 3 + 3));
      for (int a = 0; a < 2; ++a) out.mesh.uv.push_back(float(double(m.uv[v * 2 + size_t(a)]) * p.scale[a] + p.offset[a]));
    }
    for (size_t k = inst.first_index; k < inst.first_index + inst.indices; ++k)
      out.mesh.indices.push_back(uint32_t(base + (m.indices[k] - inst.first_vertex)));
    const Rect r = uv_bounds(out.mesh, base, inst.vertices);
    for (size_t j = 0; j < rects.size(); ++j)
      if (overlap(rects[j], r) && out.overlap_count++ < kMaxListedOverlaps)
        out.overlaps.push_back("'" + out.placed[j] + "' and '" + inst.node + "'");
    rects.push_back(r);
    out.placed.push_back(inst.node);
  }
  return out;
}

std::vector<Placement> identity_placements(const MeshInstances& scene, int page) {
  std::vector<Placement> out;
  for (const MeshInstance& i : scene.instances) {
    Placement p;
    p.node = i.node;
    p.page = page;
    out.push_back(p);
  }
  return out;
}

}  // namespace ahd
