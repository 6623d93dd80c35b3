#include "bakers/godot/godot_scene.h"

#include <algorithm>
#include <array>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "core/error.h"
#include "bakers/godot/godot_lmbake.h"
#include "files/input_record.h"
#include "bakers/godot/godot_tscn.h"
#include "bakers/godot/godot_unwrap_cache.h"

namespace ahd {
namespace fs = std::filesystem;

namespace {

using Affine = std::array<double, 12>;  // rows of the 3×3 basis, then the origin (Godot's text order)
const Affine kIdentity = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};

Affine compose(const Affine& a, const Affine& b) {  // a ∘ b (b applied first)
  Affine r{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j)
      r[size_t(i * 3 + j)] = a[size_t(i * 3)] * b[size_t(j)] + a[size_t(i * 3 + 1)] * b[size_t(3 + j)] + a[size_t(i * 3 + 2)] * b[size_t(6 + j)];
    r[size_t(9 + i)] = a[size_t(i * 3)] * b[9] + a[size_t(i * 3 + 1)] * b[10] + a[size_t(i * 3 + 2)] * b[11] + a[size_t(9 + i)];
  }
  return r;
}

// A mesh in its node's space, ready for the atlas: UV2 in the v-up convention of MeshTriangles.
struct Geometry {
  MeshTriangles mesh;
  std::string file;
};

struct Node {
  std::string name;
  Affine local = kIdentity;
  int parent = -1;
  std::vector<int> children;
  int geometry = -1;
  bool placeholder = false;  // an instanced file that is missing or not a scene/mesh
};

std::string godot_node_name(std::string s) {
  for (char& c : s)
    if (c == '.' || c == ':' || c == '@' || c == '/' || c == '"' || c == '%') c = '_';
  return s;
}

std::string read_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw file_error(path, "file not found");
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// [params] key of a Godot .import file, "" when absent.
std::string import_param(const std::string& import_file, const std::string& key) {
  std::ifstream f(import_file);
  std::string line;
  bool params = false;
  while (std::getline(f, line)) {
    if (!line.empty() && line[0] == '[') params = line.rfind("[params]", 0) == 0;
    if (params && line.rfind(key + "=", 0) == 0) return line.substr(key.size() + 1);
  }
  return "";
}

struct Loader {
  fs::path project;  // the folder res:// names
  std::vector<Node> nodes;
  std::vector<Geometry> geometry;
  std::vector<std::string> files, notes;
  std::set<std::string> missing;
  std::vector<std::string> stack;  // scenes being instanced (cycles)

  std::string resolve(const std::string& res, const fs::path& from_dir) const {
    if (res.rfind("res://", 0) == 0) return (project / res.substr(6)).lexically_normal().string();
    return (from_dir / res).lexically_normal().string();
  }

  int add(const std::string& name, int parent) {
    if (nodes.size() > 1000000) throw Error("Godot scene: more than a million nodes");
    Node n;
    n.name = name;
    n.parent = parent;
    nodes.push_back(n);
    const int id = int(nodes.size() - 1);
    if (parent >= 0) nodes[size_t(parent)].children.push_back(id);
    return id;
  }

  int child(int parent, const std::string& name) const {
    for (int c : nodes[size_t(parent)].children)
      if (nodes[size_t(c)].name == name) return c;
    return -1;
  }

  // "A/B" below `root` ("." = root itself); −1 when a step is missing.
  int find(int root, const std::string& path) const {
    if (path == "." || path.empty()) return root;
    int at = root;
    std::stringstream ss(path);
    std::string step;
    while (at >= 0 && std::getline(ss, step, '/')) {
      if (step == "." || step.empty()) continue;
      at = step == ".." ? nodes[size_t(at)].parent : child(at, step);
    }
    return at;
  }

  // One instance of a scene or mesh file under `parent`; returns its root node.
  int instance(const std::string& path, int parent, int depth) {
    std::string ext = fs::path(path).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (!fs::exists(path)) {
      missing.insert(path);
      const int id = add(fs::path(path).stem().string(), parent);
      nodes[size_t(id)].placeholder = true;
      return id;
    }
    if (ext == ".tscn") return scene(path, parent, depth + 1);
    if (ext == ".glb" || ext == ".gltf") return mesh_file(path, parent);
    notes.push_back(path + ": " + ext + " instances are not read (.tscn, .glb, .gltf)");
    const int id = add(fs::path(path).stem().string(), parent);
    nodes[size_t(id)].placeholder = true;
    return id;
  }

  int scene(const std::string& path, int parent, int depth) {
    if (depth > 64) throw file_error(path, "scenes nested deeper than 64");
    for (const std::string& s : stack)
      if (s == path) throw file_error(path, "instances itself (a cycle of scenes)");
    stack.push_back(path);
    files.push_back(path);
    const GodotTscn t = parse_godot_tscn(read_text(path), path);
    const fs::path dir = fs::path(path).parent_path();
    const auto ext_path = [&](const std::string& id) {
      const GodotTscnExt* e = t.find_ext(id);
      if (!e) throw file_error(path, "instance of ExtResource(\"" + id + "\"), which the scene does not declare");
      return resolve(e->path, dir);
    };
    int root = -1;
    for (const GodotTscnNode& tn : t.nodes) {
      int id;
      if (!tn.has_parent) {
        if (root >= 0) throw file_error(path, "two root nodes ('" + nodes[size_t(root)].name + "', '" + tn.name + "')");
        root = id = tn.instance.empty() ? add(tn.name, parent) : instance(ext_path(tn.instance), parent, depth);
        nodes[size_t(id)].name = tn.name;
      } else {
        if (root < 0) throw file_error(path, "node '" + tn.name + "' before the root");
        const int p = find(root, tn.parent);
        if (p < 0) continue;  // below a node this reading left out (a missing scene)
        if (!tn.instance.empty()) {
          id = instance(ext_path(tn.instance), p, depth);
          nodes[size_t(id)].name = tn.name;
        } else {
          id = child(p, tn.name);  // an override of an instanced scene's node, or a new node
          if (id < 0) id = add(tn.name, p);
        }
      }
      if (tn.has_transform) std::copy(tn.transform, tn.transform + 12, nodes[size_t(id)].local.begin());
    }
    stack.pop_back();
    return root;
  }

  // A .glb/.gltf as Godot imports it: a node named after the file holding the glTF root nodes;
  // meshes get their lightmap UVs from the unwrap cache (light_baking=2) or TEXCOORD_1.
  int mesh_file(const std::string& path, int parent) {
    files.push_back(path);
    Assimp::Importer importer;
    // No JoinIdenticalVertices: the unwrap cache indexes the accessor's vertices as stored.
    const aiScene* sc = importer.ReadFile(path, aiProcess_Triangulate | aiProcess_ValidateDataStructure);
    if (!sc || !sc->mRootNode) throw file_error(path, "cannot read mesh (" + std::string(importer.GetErrorString()) + ")");
    const std::string import_file = path + ".import", cache_file = path + ".unwrap_cache";
    const bool gen_uv2 = import_param(import_file, "meshes/light_baking") == "2";
    if (fs::exists(import_file)) files.push_back(import_file);
    std::vector<GodotUnwrapEntry> cache;
    if (gen_uv2 && fs::exists(cache_file)) {
      cache = read_godot_unwrap_cache(cache_file);
      files.push_back(cache_file);
    }
    std::vector<bool> used(cache.size(), false);
    std::map<std::vector<unsigned>, int> by_meshes;  // nodes sharing meshes share the geometry
    const int root = add(fs::path(path).stem().string(), parent);
    // Assimp's root is the glTF scene's only root node, or a synthetic "ROOT" above several.
    const aiNode* top = sc->mRootNode;
    const bool synthetic = std::string(top->mName.C_Str()) == "ROOT" && top->mNumMeshes == 0;
    std::vector<std::pair<const aiNode*, int>> todo;
    if (synthetic)
      for (unsigned c = 0; c < top->mNumChildren; ++c) todo.push_back({top->mChildren[c], root});
    else
      todo.push_back({top, root});
    while (!todo.empty()) {
      const auto [an, p] = todo.back();
      todo.pop_back();
      const int id = add(godot_node_name(an->mName.C_Str()), p);
      const aiMatrix4x4& m = an->mTransformation;
      nodes[size_t(id)].local = {m.a1, m.a2, m.a3, m.b1, m.b2, m.b3, m.c1, m.c2, m.c3, m.a4, m.b4, m.c4};
      if (an->mNumMeshes) {
        std::vector<unsigned> key(an->mMeshes, an->mMeshes + an->mNumMeshes);
        auto it = by_meshes.find(key);
        if (it == by_meshes.end()) it = by_meshes.emplace(key, node_geometry(path, sc, key, gen_uv2, cache, &used)).first;
        nodes[size_t(id)].geometry = it->second;
      }
      for (unsigned c = an->mNumChildren; c-- > 0;) todo.push_back({an->mChildren[c], id});
    }
    return root;
  }

  // The lightmap geometry of a node's meshes (−1 when it has no lightmap UVs).
  int node_geometry(const std::string& path, const aiScene* sc, const std::vector<unsigned>& meshes, bool gen_uv2,
                    const std::vector<GodotUnwrapEntry>& cache, std::vector<bool>* used) {
    std::vector<float> pos, nrm, uv1;
    std::vector<uint32_t> idx;
    bool all_uv1 = true;
    for (unsigned mi : meshes) {
      const aiMesh* m = sc->mMeshes[mi];
      if (!(m->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
      const uint32_t base = uint32_t(pos.size() / 3);
      all_uv1 = all_uv1 && m->GetNumUVChannels() >= 2;
      for (unsigned v = 0; v < m->mNumVertices; ++v) {
        pos.insert(pos.end(), {m->mVertices[v].x, m->mVertices[v].y, m->mVertices[v].z});
        const aiVector3D n = m->HasNormals() ? m->mNormals[v] : aiVector3D(0, 0, 0);
        nrm.insert(nrm.end(), {n.x, n.y, n.z});
        const aiVector3D t = m->GetNumUVChannels() >= 2 ? m->mTextureCoords[1][v] : aiVector3D(0, 0, 0);
        uv1.insert(uv1.end(), {t.x, t.y});
      }
      for (unsigned f = 0; f < m->mNumFaces; ++f)
        if (m->mFaces[f].mNumIndices == 3)
          for (unsigned k = 0; k < 3; ++k) idx.push_back(base + m->mFaces[f].mIndices[k]);
    }
    const uint32_t verts = uint32_t(pos.size() / 3);
    if (verts == 0) return -1;
    Geometry g;
    g.file = path;
    const std::string mesh_name = sc->mMeshes[meshes[0]]->mName.C_Str();
    if (gen_uv2 && !cache.empty()) {
      size_t pick = cache.size();
      for (size_t e = 0; e < cache.size() && pick == cache.size(); ++e)
        if (!(*used)[e] && cache[e].source_vertices == verts) pick = e;
      for (size_t e = 0; e < cache.size() && pick == cache.size(); ++e)  // shared by several nodes
        if (cache[e].source_vertices == verts) pick = e;
      if (pick == cache.size()) {
        notes.push_back(path + ".unwrap_cache: no entry for mesh '" + mesh_name + "' (" + std::to_string(verts) +
                        " vertices): the cache is from another version of the file; reimport it in Godot");
        return -1;
      }
      (*used)[pick] = true;
      const GodotUnwrapEntry& e = cache[pick];
      for (size_t v = 0; v < e.source_vertex.size(); ++v) {
        const size_t s = e.source_vertex[v];
        g.mesh.positions.insert(g.mesh.positions.end(), pos.begin() + std::ptrdiff_t(s * 3), pos.begin() + std::ptrdiff_t(s * 3 + 3));
        g.mesh.normals.insert(g.mesh.normals.end(), nrm.begin() + std::ptrdiff_t(s * 3), nrm.begin() + std::ptrdiff_t(s * 3 + 3));
        g.mesh.uv.insert(g.mesh.uv.end(), {e.uv2[v * 2], 1.0f - e.uv2[v * 2 + 1]});  // v down → v up
      }
      g.mesh.indices = e.indices;
    } else if (all_uv1) {
      g.mesh.positions = pos;
      g.mesh.normals = nrm;
      g.mesh.uv = uv1;  // Assimp hands glTF UVs over v up already
      g.mesh.indices = idx;
    } else {
      notes.push_back(path + ": mesh '" + mesh_name + "' has no lightmap UVs (no TEXCOORD_1" +
                      std::string(gen_uv2 ? ", no .unwrap_cache" : ", not imported with light_baking=2") + ")");
      return -1;
    }
    geometry.push_back(std::move(g));
    return int(geometry.size() - 1);
  }

  Affine world(int id) const {
    Affine m = kIdentity;
    for (int at = id; at >= 0; at = nodes[size_t(at)].parent) m = compose(nodes[size_t(at)].local, m);
    return m;
  }
};

fs::path project_root(const fs::path& tscn) {
  fs::path dir = fs::absolute(tscn).parent_path();
  for (int up = 0; up < 64; ++up) {
    if (fs::exists(dir / "project.godot")) return dir;
    if (dir == dir.parent_path()) break;
    dir = dir.parent_path();
  }
  return fs::absolute(tscn).parent_path();  // no project file: res:// is the scene's folder
}

// The geometry moved to world space (normals by the inverse transpose, renormalised).
void append_world(const MeshTriangles& g, const Affine& m, MeshTriangles* out) {
  const double* a = m.data();
  // Cofactor matrix = inverse transpose × determinant; the determinant's sign keeps orientation.
  const double c[9] = {a[4] * a[8] - a[5] * a[7], a[5] * a[6] - a[3] * a[8], a[3] * a[7] - a[4] * a[6],
                       a[2] * a[7] - a[1] * a[8], a[0] * a[8] - a[2] * a[6], a[1] * a[6] - a[0] * a[7],
                       a[1] * a[5] - a[2] * a[4], a[2] * a[3] - a[0] * a[5], a[0] * a[4] - a[1] * a[3]};
  const double det = a[0] * c[0] + a[1] * c[1] + a[2] * c[2];
  const double s = det < 0 ? -1.0 : 1.0;
  const uint32_t base = uint32_t(out->positions.size() / 3);
  for (size_t v = 0; v < g.positions.size() / 3; ++v) {
    const float* p = &g.positions[v * 3];
    const float* n = &g.normals[v * 3];
    double wn[3];
    for (int i = 0; i < 3; ++i) {
      out->positions.push_back(float(a[i * 3] * p[0] + a[i * 3 + 1] * p[1] + a[i * 3 + 2] * p[2] + a[9 + i]));
      wn[i] = s * (c[i * 3] * n[0] + c[i * 3 + 1] * n[1] + c[i * 3 + 2] * n[2]);
    }
    const double len = std::sqrt(wn[0] * wn[0] + wn[1] * wn[1] + wn[2] * wn[2]);
    for (double x : wn) out->normals.push_back(len > 0 && std::isfinite(len) ? float(x / len) : 0.0f);
  }
  out->uv.insert(out->uv.end(), g.uv.begin(), g.uv.end());
  for (uint32_t i : g.indices) out->indices.push_back(base + i);
}


// The lightmap's users (`data`, read from `lmbake`) as instances of the loaded nodes' geometry, where `resolve`
// finds a user's node from its path (−1: not in the scene). `from` names the scene in the error.
template <class Resolve>
GodotSceneMeshes place_users(Loader& L, const std::string& lmbake, const GodotLightmapData& data, const std::string& from,
                             const Resolve& resolve) {
  GodotSceneMeshes out;
  out.lmbake = lmbake;
  L.files.push_back(lmbake);
  out.users = int(data.users.size());
  int no_node = 0, no_mesh = 0, grid = 0;
  for (const GodotLightmapUser& u : data.users) {
    if (u.sub_instance >= 0) {
      ++grid;
      continue;
    }
    const int id = u.path.empty() || u.path[0] == '/' ? -1 : resolve(u.path);
    if (id < 0) {
      ++no_node;
      continue;
    }
    const Node& n = L.nodes[size_t(id)];
    if (n.geometry < 0) {
      ++no_mesh;
      continue;
    }
    MeshInstance inst;
    inst.node = u.path;
    inst.first_vertex = out.scene.mesh.positions.size() / 3;
    inst.first_index = out.scene.mesh.indices.size();
    append_world(L.geometry[size_t(n.geometry)].mesh, L.world(id), &out.scene.mesh);
    inst.vertices = out.scene.mesh.positions.size() / 3 - inst.first_vertex;
    inst.indices = out.scene.mesh.indices.size() - inst.first_index;
    out.scene.instances.push_back(inst);
    Placement p;
    p.node = u.path;
    p.page = u.slice;
    // Godot samples position + uv2 · size with v down; MeshTriangles' v is up: v' = 1 − v.
    p.scale[0] = u.rect[2], p.scale[1] = u.rect[3];
    p.offset[0] = u.rect[0], p.offset[1] = 1.0 - u.rect[1] - u.rect[3];
    out.placements.push_back(p);
  }
  out.notes = L.notes;
  for (const std::string& m : L.missing) out.notes.push_back(m + ": instanced but not in the project (left out)");
  if (no_node) out.notes.push_back(std::to_string(no_node) + " lightmap user(s) not found in the scene (their scenes are missing)");
  if (no_mesh) out.notes.push_back(std::to_string(no_mesh) + " lightmap user(s) without a mesh with lightmap UVs here");
  if (grid) out.notes.push_back(std::to_string(grid) + " GridMap cell user(s) not read");
  out.files = L.files;
  for (const std::string& f : out.files) note_input_file(f);  // the depfile and the cache key (files/input_record.h)
  if (out.scene.instances.empty())
    throw file_error(lmbake, "none of its " + std::to_string(data.users.size()) + " users is a mesh with lightmap UVs in " + from +
                                 (out.notes.empty() ? "" : " (" + out.notes.front() + ")"));
  return out;
}

}  // namespace

GodotSceneMeshes load_godot_scene(const std::string& tscn, const std::string& lmbake_override) {
  Loader L;
  L.project = project_root(tscn);
  const int root = L.scene(fs::path(tscn).lexically_normal().string(), -1, 0);

  // The LightmapGI node of the top scene (its light_data names the .lmbake).
  const GodotTscn top = parse_godot_tscn(read_text(tscn), tscn);
  int gi = -1;
  std::string lmbake = lmbake_override;
  for (const GodotTscnNode& tn : top.nodes) {
    if (tn.type != "LightmapGI") continue;
    gi = tn.has_parent ? L.find(root, tn.parent == "." ? tn.name : tn.parent + "/" + tn.name) : root;
    if (lmbake.empty() && !tn.light_data.empty())
      if (const GodotTscnExt* e = top.find_ext(tn.light_data)) lmbake = L.resolve(e->path, fs::path(tscn).parent_path());
    break;
  }
  if (gi < 0) throw file_error(tscn, "no LightmapGI node: not the scene that was baked (give the scene holding the LightmapGI)");
  if (lmbake.empty()) throw file_error(tscn, "the LightmapGI has no light_data (.lmbake): bake it in Godot first");

  return place_users(L, lmbake, read_godot_lmbake(lmbake), tscn, [&](const std::string& path) { return L.find(gi, path); });
}

GodotSceneMeshes load_godot_export(const std::string& gltf, const std::string& lmbake) {
  Loader L;
  L.project = fs::absolute(gltf).parent_path();
  L.mesh_file(fs::path(gltf).lexically_normal().string(), -1);
  const GodotLightmapData data = read_godot_lmbake(lmbake);
  // The users' paths are relative to the LightmapGI, which the export may leave out: a path
  // "../A/B" names A/B under the LightmapGI's parent, any other path a node below the LightmapGI.
  // Its place is the node under which the most users find a mesh (the first such, nearest the root).
  const auto resolve_at = [&L](int at, const std::string& path) {
    return path.rfind("../", 0) == 0 ? L.find(at, path.substr(3)) : L.find(at, path);
  };
  if (double(L.nodes.size()) * double(data.users.size()) > 5e7)
    throw file_error(gltf, "too many nodes (" + std::to_string(L.nodes.size()) + ") for the .lmbake's " +
                               std::to_string(data.users.size()) + " users to be placed by name");
  int best = -1, best_found = 0;
  for (size_t at = 0; at < L.nodes.size(); ++at) {
    if (L.nodes[at].children.empty()) continue;
    int found = 0;
    for (const GodotLightmapUser& u : data.users) {
      if (u.sub_instance >= 0 || u.path.empty() || u.path[0] == '/') continue;
      const int id = resolve_at(int(at), u.path);
      found += id >= 0 && L.nodes[size_t(id)].geometry >= 0;
    }
    if (found > best_found) best = int(at), best_found = found;
  }
  if (best < 0)
    throw file_error(gltf, "no node of the .lmbake's users (" + lmbake + ") is a mesh with TEXCOORD_1 here: export the baked "
                               "scene from Godot's editor (Scene > Export As > glTF 2.0) with its lightmap UVs");
  return place_users(L, lmbake, data, gltf, [&](const std::string& path) { return resolve_at(best, path); });
}

std::string find_godot_scene(const std::string& exr) {
  const fs::path p(exr);
  const std::string want = p.stem().string() + ".lmbake";
  std::error_code ec;
  std::vector<std::string> found;
  for (const auto& e : fs::directory_iterator(p.parent_path().empty() ? fs::path(".") : p.parent_path(), ec)) {
    if (!e.is_regular_file() || e.path().extension() != ".tscn") continue;
    std::ifstream f(e.path());
    std::string line;
    while (std::getline(f, line))
      if (line.rfind("[ext_resource", 0) == 0 && line.find("LightmapGIData") != std::string::npos &&
          line.find("/" + want + "\"") != std::string::npos) {
        found.push_back(e.path().string());
        break;
      }
  }
  std::sort(found.begin(), found.end());
  return found.empty() ? "" : found.front();
}

}  // namespace ahd
