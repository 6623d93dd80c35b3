#include "bakers/godot/godot_fbx.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <set>

#include "core/error.h"
#include "scene/mesh_io.h"

namespace ahd {

namespace {

// The scene's metadata entry `key` of type T (aiMetadata::Get: the key's first entry, of that type).
template <class T>
bool meta(const std::map<std::string, T>& entries, const char* key, T* out) {
  const auto it = entries.find(key);
  if (it == entries.end()) return false;
  *out = it->second;
  return true;
}

int meta_int(const ImportedScene& sc, const char* key, int fallback) {
  int32_t i = 0;
  if (meta(sc.meta_int32, key, &i)) return i;
  return fallback;
}

double meta_real(const ImportedScene& sc, const char* key, double fallback) {
  double d = 0;
  if (meta(sc.meta_double, key, &d)) return d;
  float f = 0;
  if (meta(sc.meta_float, key, &f)) return f;
  return fallback;
}

// Godot's String::validate_node_name.
std::string node_name(std::string s) {
  for (char& c : s)
    if (c == '.' || c == ':' || c == '@' || c == '/' || c == '"' || c == '%') c = '_';
  return s;
}

// FBXDocument::_gen_unique_name: the validated name, then name2, name3, … until unused.
std::string unique_name(std::set<std::string>* used, const std::string& name) {
  const std::string base = node_name(name);
  std::string u = base;
  for (int i = 2; used->count(u); ++i) u = base + std::to_string(i);
  used->insert(u);
  return u;
}

const double kNoAxes[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};

struct Conversion {
  double s = 1;                               // metres per file unit
  double a[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};  // file axes → Godot's (rows)
  void point(const float* v, double scale, float* out) const {
    const double p[3] = {v[0], v[1], v[2]};
    for (int i = 0; i < 3; ++i) out[i] = float(scale * (a[i * 3] * p[0] + a[i * 3 + 1] * p[1] + a[i * 3 + 2] * p[2]));
  }
};

// ufbx's space conversion: the file's right (CoordAxis), up (UpAxis) and front (FrontAxis) axes,
// each with its sign, become +X, +Y, +Z; its unit (UnitScaleFactor centimetres) becomes metres,
// snapped to a power of ten when within rounding of one.
Conversion conversion(const ImportedScene& sc, bool* mirrored) {
  Conversion c;
  const int axis[3] = {meta_int(sc, "CoordAxis", 0), meta_int(sc, "UpAxis", 1), meta_int(sc, "FrontAxis", 2)};
  const int sign[3] = {meta_int(sc, "CoordAxisSign", 1), meta_int(sc, "UpAxisSign", 1),
                       meta_int(sc, "FrontAxisSign", 1)};
  bool valid = true;
  for (int i = 0; i < 3; ++i) valid = valid && axis[i] >= 0 && axis[i] < 3 && (sign[i] == 1 || sign[i] == -1);
  valid = valid && axis[0] != axis[1] && axis[1] != axis[2] && axis[0] != axis[2];
  if (valid) {
    std::fill(c.a, c.a + 9, 0.0);
    for (int i = 0; i < 3; ++i) c.a[i * 3 + axis[i]] = sign[i];
  }
  const double det = c.a[0] * (c.a[4] * c.a[8] - c.a[5] * c.a[7]) - c.a[1] * (c.a[3] * c.a[8] - c.a[5] * c.a[6]) +
                     c.a[2] * (c.a[3] * c.a[7] - c.a[4] * c.a[6]);
  *mirrored = det < 0;
  double s = meta_real(sc, "UnitScaleFactor", 1.0) * 0.01;
  if (!(s > 0) || !std::isfinite(s)) s = 0.01;
  const double p = std::pow(10.0, std::round(std::log10(s)));
  if (std::fabs(s - p) <= p * 1e-6) s = p;
  c.s = s;
  return c;
}

// ufbx's triangles of a face (checked against Godot 4.6's FBXDocument): a triangle as it is; a
// quad split along its shorter diagonal, 0-2 when they are equal: (0, 1, 2), (2, 3, 0) or (1, 2, 3),
// (3, 0, 1); more corners: a fan here, which ufbx's own split need not match (*exact = false).
void face_triangles(const ImportedMesh& am, size_t face, double s, std::vector<unsigned>* out, bool* exact) {
  const uint32_t* c = am.face(face);
  const unsigned n = am.face_size(face);
  if (n == 3) {
    out->insert(out->end(), {c[0], c[1], c[2]});
  } else if (n == 4) {
    const auto d2 = [&](unsigned a, unsigned b) {
      const float* p = &am.positions[size_t(c[a]) * 3];
      const float* q = &am.positions[size_t(c[b]) * 3];
      const double x = s * double(p[0]) - s * double(q[0]), y = s * double(p[1]) - s * double(q[1]),
                   z = s * double(p[2]) - s * double(q[2]);
      return x * x + y * y + z * z;
    };
    if (d2(0, 2) <= d2(1, 3)) out->insert(out->end(), {c[0], c[1], c[2], c[2], c[3], c[0]});
    else out->insert(out->end(), {c[1], c[2], c[3], c[3], c[0], c[1]});
  } else if (n > 4) {
    for (unsigned k = 1; k + 1 < n; ++k) out->insert(out->end(), {c[0], c[k], c[k + 1]});
    *exact = false;
  }
}

// One surface (an aiMesh: one material part) merged as SurfaceTool::index() merges corners,
// appended to `m`. Positions in metres (s·p: MODIFY_GEOMETRY scales the geometry and leaves the
// axis conversion to the root nodes' transforms); normals and tangents as the file stores them.
void append_surface(const ImportedMesh& am, const Conversion& c, GodotFbxMesh* m) {
  std::map<std::string, uint32_t> seen;
  const bool has_n = !am.normals.empty(), has_t = !am.tangents.empty() && !am.bitangents.empty(),
             has_c = !am.colors.empty();
  m->has_normals = m->has_normals && has_n;
  std::vector<unsigned> uv_sets;
  for (unsigned k = 0; k < kImportedUvSets && k < 8; ++k)
    if (!am.uv[k].empty()) uv_sets.push_back(k);
  const bool has_uv2 = !am.uv[1].empty();
  const auto put = [](const std::vector<float>& a, unsigned v, double scale, float* out) {
    const float* p = &a[size_t(v) * 3];
    out[0] = float(scale * p[0]), out[1] = float(scale * p[1]), out[2] = float(scale * p[2]);
  };
  std::vector<unsigned> tri;
  bool exact = true;
  for (size_t f = 0; f < am.faces(); ++f) {
    tri.clear();
    face_triangles(am, f, c.s, &tri, &exact);  // points and lines are other surfaces
    for (size_t t = 0; t + 2 < tri.size(); t += 3)
      // Godot's triangle c, b, a, decoded in that order (the order of first use).
      for (int k = 2; k >= 0; --k) {
        const unsigned v = tri[t + size_t(k)];
        float key[3 + 3 + 6 + 16 + 4];
        size_t n = 0;
        put(am.positions, v, c.s, key), n += 3;
        if (has_n) put(am.normals, v, 1.0, key + n), n += 3;
        if (has_t) put(am.tangents, v, 1.0, key + n), put(am.bitangents, v, 1.0, key + n + 3), n += 6;
        for (unsigned set : uv_sets) key[n++] = am.uv[set][size_t(v) * 2], key[n++] = am.uv[set][size_t(v) * 2 + 1];
        if (has_c) {
          const float* col = &am.colors[size_t(v) * 4];
          key[n++] = col[0], key[n++] = col[1], key[n++] = col[2], key[n++] = col[3];
        }
        const std::string bytes(reinterpret_cast<const char*>(key), n * sizeof(float));
        auto [it, added] = seen.emplace(bytes, uint32_t(m->positions.size() / 3));
        if (added) {
          m->positions.insert(m->positions.end(), key, key + 3);
          if (has_n) m->normals.insert(m->normals.end(), key + 3, key + 6);
          else m->normals.insert(m->normals.end(), {0.0f, 0.0f, 0.0f});
          const float* uv = has_uv2 ? &am.uv[1][size_t(v) * 2] : nullptr;
          m->uv2.insert(m->uv2.end(), {uv ? uv[0] : 0.0f, uv ? uv[1] : 0.0f});
        }
        m->indices.push_back(it->second);
      }
  }
  m->polygons = m->polygons || !exact;
}

}  // namespace

GodotFbxScene read_godot_fbx(const std::string& path) {
  // Pivots folded into each node's transform (Godot: ufbx's ADJUST_TO_PIVOT), no helper nodes:
  // kImportFbxNoPivots. Faces kept as the file has them: they are triangulated as ufbx does
  // (face_triangles). Through the one Assimp import (scene/mesh_io.h): read once, bounded, Assimp's
  // logger locked.
  const ImportedScene sc = import_mesh_file(path, kImportFbxNoPivots | kImportValidateDataStructure);
  GodotFbxScene out;
  const Conversion c = conversion(sc, &out.mirrored);
  out.unit_scale = c.s;

  std::set<std::string> used = {"Skeleton3D", "RootNode"};  // reserved; the FBX root is "RootNode"
  std::map<std::vector<unsigned>, int> mesh_of;             // a node's aiMeshes → one Godot mesh
  struct Todo {
    const ImportedNode* n;
    int parent;
  };
  std::vector<Todo> todo;
  const ImportedNode& root = sc.nodes[0];
  for (size_t k = root.children.size(); k-- > 0;) todo.push_back({&sc.nodes[root.children[k]], -1});
  while (!todo.empty()) {
    const Todo t = todo.back();
    todo.pop_back();
    if (out.nodes.size() > 1000000) throw file_error(path, "more than a million nodes");
    GodotFbxNode gn;
    gn.parent = t.parent;
    const std::string& raw = t.n->name;
    gn.name = unique_name(&used, raw.empty() ? (!t.n->meshes.empty() ? "Mesh" : "Node") : raw);
    // Godot's local transform (as Godot 4.6's FBXDocument gives it): translations in metres; the
    // axis conversion A only on the file's root nodes (basis A·B, origin s·A·t), as their parent.
    const std::array<float, 16>& m = t.n->transform;  // rows a1 a2 a3 a4, b1 …
    const double b[9] = {m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10]};
    Conversion by = c;
    if (t.parent >= 0) std::copy(kNoAxes, kNoAxes + 9, by.a);
    const double* a = by.a;
    double r[9];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r[i * 3 + j] = a[i * 3] * b[j] + a[i * 3 + 1] * b[3 + j] + a[i * 3 + 2] * b[6 + j];
    float origin[3];
    const float t3[3] = {m[3], m[7], m[11]};
    by.point(t3, c.s, origin);
    gn.local = {float(r[0]), float(r[1]), float(r[2]), origin[0], float(r[3]), float(r[4]), float(r[5]), origin[1],
                float(r[6]), float(r[7]), float(r[8]), origin[2], 0,           0,           0,           1};
    if (!t.n->meshes.empty()) {
      const std::vector<unsigned>& parts = t.n->meshes;
      auto it = mesh_of.find(parts);
      if (it == mesh_of.end()) {
        GodotFbxMesh gm;
        gm.name = sc.meshes[parts[0]].name;
        if (gm.name.empty()) gm.name = gn.name;
        for (unsigned p : parts) {
          if (p >= sc.meshes.size()) continue;
          append_surface(sc.meshes[p], c, &gm);
        }
        if (!gm.uv2.empty()) {
          bool any_uv2 = false;
          for (unsigned p : parts) any_uv2 = any_uv2 || (p < sc.meshes.size() && !sc.meshes[p].uv[1].empty());
          if (!any_uv2) gm.uv2.clear();
        }
        out.meshes.push_back(std::move(gm));
        it = mesh_of.emplace(parts, int(out.meshes.size() - 1)).first;
      }
      gn.mesh = it->second;
    }
    out.nodes.push_back(gn);
    const int id = int(out.nodes.size() - 1);
    for (size_t k = t.n->children.size(); k-- > 0;) todo.push_back({&sc.nodes[t.n->children[k]], id});
  }
  return out;
}

}  // namespace ahd
