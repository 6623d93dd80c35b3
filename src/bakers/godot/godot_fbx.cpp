#include "bakers/godot/godot_fbx.h"

#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <cmath>
#include <cstring>
#include <map>
#include <set>

#include "core/error.h"

namespace ahd {

namespace {

template <class T>
bool meta(const aiScene* sc, const char* key, T* out) {
  return sc->mMetaData && sc->mMetaData->Get(key, *out);
}

int meta_int(const aiScene* sc, const char* key, int fallback) {
  int32_t i = 0;
  if (meta(sc, key, &i)) return i;
  return fallback;
}

double meta_real(const aiScene* sc, const char* key, double fallback) {
  double d = 0;
  if (meta(sc, key, &d)) return d;
  float f = 0;
  if (meta(sc, key, &f)) return f;
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

struct Conversion {
  double s = 1;                               // metres per file unit
  double a[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};  // file axes → Godot's (rows)
  void point(const aiVector3D& v, double scale, float* out) const {
    const double p[3] = {v.x, v.y, v.z};
    for (int i = 0; i < 3; ++i) out[i] = float(scale * (a[i * 3] * p[0] + a[i * 3 + 1] * p[1] + a[i * 3 + 2] * p[2]));
  }
};

// ufbx's space conversion: the file's right (CoordAxis), up (UpAxis) and front (FrontAxis) axes,
// each with its sign, become +X, +Y, +Z; its unit (UnitScaleFactor centimetres) becomes metres,
// snapped to a power of ten when within rounding of one.
Conversion conversion(const aiScene* sc, bool* mirrored) {
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

// One surface (an aiMesh: one material part) merged as SurfaceTool::index() merges corners,
// appended to `m`.
void append_surface(const aiMesh* am, const Conversion& c, GodotFbxMesh* m) {
  std::map<std::string, uint32_t> seen;
  const bool has_n = am->HasNormals(), has_t = am->HasTangentsAndBitangents(), has_c = am->HasVertexColors(0);
  m->has_normals = m->has_normals && has_n;
  std::vector<unsigned> uv_sets;
  for (unsigned k = 0; k < AI_MAX_NUMBER_OF_TEXTURECOORDS && k < 8; ++k)
    if (am->HasTextureCoords(k)) uv_sets.push_back(k);
  const bool has_uv2 = am->HasTextureCoords(1);
  for (unsigned f = 0; f < am->mNumFaces; ++f) {
    const aiFace& face = am->mFaces[f];
    if (face.mNumIndices != 3) continue;  // points and lines are other surfaces
    // Godot's triangle c, b, a, decoded in that order (the order of first use).
    for (int k = 2; k >= 0; --k) {
      const unsigned v = face.mIndices[k];
      float key[3 + 3 + 6 + 16 + 4];
      size_t n = 0;
      c.point(am->mVertices[v], c.s, key + n), n += 3;
      if (has_n) c.point(am->mNormals[v], 1.0, key + n), n += 3;
      if (has_t) c.point(am->mTangents[v], 1.0, key + n), c.point(am->mBitangents[v], 1.0, key + n + 3), n += 6;
      for (unsigned set : uv_sets) key[n++] = am->mTextureCoords[set][v].x, key[n++] = am->mTextureCoords[set][v].y;
      if (has_c) {
        const aiColor4D& col = am->mColors[0][v];
        key[n++] = col.r, key[n++] = col.g, key[n++] = col.b, key[n++] = col.a;
      }
      const std::string bytes(reinterpret_cast<const char*>(key), n * sizeof(float));
      auto [it, added] = seen.emplace(bytes, uint32_t(m->positions.size() / 3));
      if (added) {
        m->positions.insert(m->positions.end(), key, key + 3);
        if (has_n) m->normals.insert(m->normals.end(), key + 3, key + 6);
        else m->normals.insert(m->normals.end(), {0.0f, 0.0f, 0.0f});
        const aiVector3D t = has_uv2 ? am->mTextureCoords[1][v] : aiVector3D(0, 0, 0);
        m->uv2.insert(m->uv2.end(), {t.x, t.y});
      }
      m->indices.push_back(it->second);
    }
  }
}

}  // namespace

GodotFbxScene read_godot_fbx(const std::string& path) {
  Assimp::Importer importer;
  // Pivots folded into each node's transform (Godot: ufbx's ADJUST_TO_PIVOT), no helper nodes.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS, false);
  const aiScene* sc = importer.ReadFile(path, aiProcess_ValidateDataStructure);
  if (!sc || !sc->mRootNode) throw file_error(path, "cannot read FBX (" + std::string(importer.GetErrorString()) + ")");
  // Which meshes have faces of more than 3 corners (before Assimp triangulates them).
  std::vector<bool> polygon_mesh(sc->mNumMeshes, false);
  for (unsigned i = 0; i < sc->mNumMeshes; ++i)
    polygon_mesh[i] = (sc->mMeshes[i]->mPrimitiveTypes & aiPrimitiveType_POLYGON) != 0;
  sc = importer.ApplyPostProcessing(aiProcess_Triangulate);
  if (!sc || !sc->mRootNode) throw file_error(path, "cannot read FBX (" + std::string(importer.GetErrorString()) + ")");
  GodotFbxScene out;
  const Conversion c = conversion(sc, &out.mirrored);
  out.unit_scale = c.s;

  std::set<std::string> used = {"Skeleton3D", "RootNode"};  // reserved; the FBX root is "RootNode"
  std::map<std::vector<unsigned>, int> mesh_of;             // a node's aiMeshes → one Godot mesh
  struct Todo {
    const aiNode* n;
    int parent;
  };
  std::vector<Todo> todo;
  for (unsigned k = sc->mRootNode->mNumChildren; k-- > 0;) todo.push_back({sc->mRootNode->mChildren[k], -1});
  while (!todo.empty()) {
    const Todo t = todo.back();
    todo.pop_back();
    if (out.nodes.size() > 1000000) throw file_error(path, "more than a million nodes");
    GodotFbxNode gn;
    gn.parent = t.parent;
    const std::string raw = t.n->mName.C_Str();
    gn.name = unique_name(&used, raw.empty() ? (t.n->mNumMeshes ? "Mesh" : "Node") : raw);
    // Godot's local transform: the conversion C = s·A conjugating the file's (basis A·B·Aᵀ, origin s·A·t).
    const aiMatrix4x4& m = t.n->mTransformation;
    const double b[9] = {m.a1, m.a2, m.a3, m.b1, m.b2, m.b3, m.c1, m.c2, m.c3};
    const double* a = c.a;
    double ab[9], r[9];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) ab[i * 3 + j] = a[i * 3] * b[j] + a[i * 3 + 1] * b[3 + j] + a[i * 3 + 2] * b[6 + j];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        r[i * 3 + j] = ab[i * 3] * a[j * 3] + ab[i * 3 + 1] * a[j * 3 + 1] + ab[i * 3 + 2] * a[j * 3 + 2];
    float origin[3];
    c.point(aiVector3D(m.a4, m.b4, m.c4), c.s, origin);
    gn.local = {float(r[0]), float(r[1]), float(r[2]), origin[0], float(r[3]), float(r[4]), float(r[5]), origin[1],
                float(r[6]), float(r[7]), float(r[8]), origin[2], 0,           0,           0,           1};
    if (t.n->mNumMeshes) {
      const std::vector<unsigned> parts(t.n->mMeshes, t.n->mMeshes + t.n->mNumMeshes);
      auto it = mesh_of.find(parts);
      if (it == mesh_of.end()) {
        GodotFbxMesh gm;
        gm.name = sc->mMeshes[parts[0]]->mName.C_Str();
        if (gm.name.empty()) gm.name = gn.name;
        for (unsigned p : parts) {
          if (p >= sc->mNumMeshes) continue;
          append_surface(sc->mMeshes[p], c, &gm);
          gm.polygons = gm.polygons || polygon_mesh[p];
        }
        if (!gm.uv2.empty()) {
          bool any_uv2 = false;
          for (unsigned p : parts) any_uv2 = any_uv2 || (p < sc->mNumMeshes && sc->mMeshes[p]->HasTextureCoords(1));
          if (!any_uv2) gm.uv2.clear();
        }
        out.meshes.push_back(std::move(gm));
        it = mesh_of.emplace(parts, int(out.meshes.size() - 1)).first;
      }
      gn.mesh = it->second;
    }
    out.nodes.push_back(gn);
    const int id = int(out.nodes.size() - 1);
    for (unsigned k = t.n->mNumChildren; k-- > 0;) todo.push_back({t.n->mChildren[k], id});
  }
  return out;
}

}  // namespace ahd
