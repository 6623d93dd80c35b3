#include "bakers/godot/godot_scene.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>

#include "bakers/godot/godot_fbx.h"
#include "bakers/godot/godot_mesh_resource.h"
#include "bakers/godot/godot_obj.h"
#include "bakers/godot/godot_unwrap_key.h"
#include "core/error.h"
#include "bakers/godot/godot_lmbake.h"
#include "files/input_file.h"
#include "files/input_record.h"
#include "scene/assimp_math.h"
#include "scene/mesh_io.h"
#include "bakers/godot/godot_tscn.h"
#include "bakers/godot/godot_unwrap_cache.h"
#include "files/utf8_path.h"
#include <nlohmann/json.hpp>

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
  std::string why;           // why it has no geometry (for the users left out), "" when not known
  bool placeholder = false;  // an instanced file that is missing or not a scene/mesh
};

std::string godot_node_name(std::string s) {
  for (char& c : s)
    if (c == '.' || c == ':' || c == '@' || c == '/' || c == '"' || c == '%') c = '_';
  return s;
}

// Scene text (.tscn, .tres, project.godot, .import, .obj) through the opener (files/input_file.h).
std::string read_text(const std::string& path) { return read_input_text(path, InputKind::kSceneText); }

// Whether a .glb/.gltf (`bytes`, the file Assimp parsed) declares the extension GODOT_single_root
// (Godot's own glTF export): its JSON's "extensionsUsed". False for a file that cannot be read as
// such (Assimp reports those).
bool gltf_single_root(const std::vector<uint8_t>& bytes) {
  const char* json = reinterpret_cast<const char*>(bytes.data());
  size_t json_size = bytes.size();
  if (bytes.size() >= 20 && std::memcmp(json, "glTF", 4) == 0) {  // GLB: header, then the JSON chunk
    uint32_t len = 0;
    std::memcpy(&len, bytes.data() + 12, 4);
    if (std::memcmp(json + 16, "JSON", 4) != 0 || len > bytes.size() - 20) return false;
    json += 20, json_size = len;
  }
  const nlohmann::json j = nlohmann::json::parse(json, json + json_size, nullptr, false);
  if (j.is_discarded() || !j.is_object() || !j.contains("extensionsUsed") || !j["extensionsUsed"].is_array())
    return false;
  for (const auto& e : j["extensionsUsed"])
    if (e.is_string() && e.get<std::string>() == "GODOT_single_root") return true;
  return false;
}

// [params] key of a Godot .import file, "" when absent.
std::string import_param(const std::string& import_file, const std::string& key) {
  if (!probe_input_file(import_file)) return "";  // a probe: an .import appearing later changes the result
  std::istringstream f(read_input_text(import_file, InputKind::kSceneText));
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

  // A path a project file (`file`) names, res:// or relative to its folder, kept inside the project:
  // "res://../x", an absolute path and a symlink leading out are refused with one error line
  // (docs/robustness-input.md "Reader input files").
  // Resolved once per (path, folder): a scene instanced a million times asks a million times.
  mutable std::map<std::pair<std::string, std::string>, std::string> resolved;
  std::string resolve(const std::string& res, const fs::path& from_dir, const std::string& file) const {
    const auto key = std::make_pair(res, utf8_string(from_dir));
    if (const auto it = resolved.find(key); it != resolved.end()) return it->second;
    std::string r = resolve_once(res, from_dir, file);
    resolved.emplace(key, r);
    return r;
  }
  std::string resolve_once(const std::string& res, const fs::path& from_dir, const std::string& file) const {
    const bool is_res = res.rfind("res://", 0) == 0;
    if (!is_res && (fs_path(res).is_absolute() || res.find("://") != std::string::npos))
      throw file_error(file, "path '" + res + "' is outside the project (" + utf8_string(project) + ")");
    const fs::path p = (is_res ? project / fs_path(res.substr(6)) : from_dir / fs_path(res)).lexically_normal();
    std::error_code ec;
    const fs::path root = fs::absolute(project, ec).lexically_normal();
    const fs::path rel = fs::absolute(p, ec).lexically_normal().lexically_relative(root);
    bool inside = !ec && !rel.empty() && *rel.begin() != "..";
    if (inside && fs::exists(fs::symlink_status(p, ec)) && fs::exists(p, ec)) {  // symlinks resolved
      const fs::path c = fs::canonical(p, ec), croot = fs::canonical(project, ec);
      const fs::path crel = c.lexically_relative(croot);
      inside = !ec && !crel.empty() && *crel.begin() != "..";
    }
    if (!inside) throw file_error(file, "path '" + res + "' leads outside the project (" + utf8_string(project) + ")");
    return shortest(p);
  }

  // Each file once in `files`, in the order first read (a scene instanced 10 000 times is one file).
  std::set<std::string> listed;
  void add_file(const std::string& f) {
    if (listed.insert(f).second) files.push_back(f);
  }

  // Each scene parsed once however often it is instanced.
  std::map<std::string, std::shared_ptr<const GodotTscn>> parsed;
  const GodotTscn& parsed_scene(const std::string& path) {
    auto it = parsed.find(path);
    if (it == parsed.end())
      it = parsed.emplace(path, std::make_shared<const GodotTscn>(parse_godot_tscn(read_text(path), path))).first;
    return *it->second;
  }

  // Each mesh file (.glb, .gltf, .fbx) imported once: the nodes its first instance made, replayed
  // for later instances (their geometry shared by index, not copied).
  std::map<std::string, std::vector<Node>> file_nodes;
  void keep_nodes(const std::string& path, int root) {
    std::vector<Node> t(nodes.begin() + root, nodes.end());
    for (size_t k = 0; k < t.size(); ++k) t[k].parent = k == 0 ? -1 : t[k].parent - root, t[k].children.clear();
    file_nodes.emplace(path, std::move(t));
  }
  int replay_nodes(const std::vector<Node>& t, int parent) {
    if (nodes.size() + t.size() > kMaxNodes) throw Error("Godot scene: more than a million nodes");
    const int base = int(nodes.size());
    for (size_t k = 0; k < t.size(); ++k) {
      Node n = t[k];
      n.parent = k == 0 ? parent : base + n.parent;
      nodes.push_back(std::move(n));
      if (nodes.back().parent >= 0) nodes[size_t(nodes.back().parent)].children.push_back(int(nodes.size() - 1));
    }
    return base;
  }
  static constexpr size_t kMaxNodes = 1000000;

  std::map<std::string, bool> exists_cache;  // instanced files, tested once each

  // Child-name comparisons made by find (the editor-export search is bounded by them).
  mutable uint64_t steps = 0;

  // A relative path that climbs out of the working folder ("../scenes/a.tscn" seen from scenes/)
  // spelt from the working folder ("a.tscn"); any other path as it is.
  static std::string shortest(const fs::path& p) {
    if (p.is_relative() && !p.empty() && *p.begin() == "..") {
      std::error_code ec;
      const fs::path r = fs::relative(p, ec);
      if (!ec && !r.empty()) return utf8_string(r);
    }
    return utf8_string(p);
  }

  int add(const std::string& name, int parent) {
    if (nodes.size() > kMaxNodes) throw Error("Godot scene: more than a million nodes");
    Node n;
    n.name = name;
    n.parent = parent;
    nodes.push_back(n);
    const int id = int(nodes.size() - 1);
    if (parent >= 0) nodes[size_t(parent)].children.push_back(id);
    return id;
  }

  int child(int parent, const std::string& name) const {
    steps += nodes[size_t(parent)].children.size() + 1;
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
    std::string ext = utf8_string(fs_path(path).extension());
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    auto there = exists_cache.find(path);
    if (there == exists_cache.end()) there = exists_cache.emplace(path, input_exists(path)).first;
    if (!there->second) {
      missing.insert(path);
      const int id = add(utf8_string(fs_path(path).stem()), parent);
      nodes[size_t(id)].placeholder = true;
      return id;
    }
    if (ext == ".tscn") return scene(path, parent, depth + 1);
    if (ext == ".glb" || ext == ".gltf" || ext == ".fbx") {
      const auto it = file_nodes.find(path);
      if (it != file_nodes.end()) return replay_nodes(it->second, parent);
      const int root = ext == ".fbx" ? fbx_file(path, parent) : mesh_file(path, parent);
      keep_nodes(path, root);
      return root;
    }
    notes.push_back(
        path + ": " + ext + " instances are not read (.tscn, .glb, .gltf, .fbx are): " +
        (ext == ".scn"
             ? "save the scene as text (.tscn) in Godot"
             : "export it as glTF (.glb) with its lightmap UVs, or give the scene's glTF export with --godot-scene"));
    const int id = add(utf8_string(fs_path(path).stem()), parent);
    nodes[size_t(id)].placeholder = true;
    return id;
  }

  int scene(const std::string& path, int parent, int depth) {
    if (depth > 64) throw file_error(path, "scenes nested deeper than 64");
    for (const std::string& s : stack)
      if (s == path) throw file_error(path, "instances itself (a cycle of scenes)");
    stack.push_back(path);
    add_file(path);
    const GodotTscn& t = parsed_scene(path);
    const fs::path dir = fs_path(path).parent_path();
    const auto ext_path = [&](const std::string& id) {
      const GodotTscnExt* e = t.find_ext(id);
      if (!e) throw file_error(path, "instance of ExtResource(\"" + id + "\"), which the scene does not declare");
      return resolve(e->path, dir, path);
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
      if (!tn.mesh_sub.empty() || !tn.mesh_ext.empty()) resource_mesh(t, tn, path, dir, id);
    }
    stack.pop_back();
    return root;
  }

  // `mesh = SubResource(…)` / `mesh = ExtResource(…)` on a node: the mesh defined in the scene or
  // named as a resource file (bakers/godot/godot_mesh_resource.h), replacing an instanced node's.
  // A mesh that cannot be read leaves the node without geometry and says why.
  std::map<std::string, std::pair<int, std::string>> resource_meshes;  // scene|sub id or file -> geometry, why
  void resource_mesh(const GodotTscn& t, const GodotTscnNode& tn, const std::string& path, const fs::path& dir,
                     int id) {
    std::string key, file = path;
    const GodotTscnSub* sub = nullptr;
    if (!tn.mesh_sub.empty()) {
      sub = t.find_sub(tn.mesh_sub);
      key = path + "|" + tn.mesh_sub;
    } else if (const GodotTscnExt* e = t.find_ext(tn.mesh_ext)) {
      file = resolve(e->path, dir, path);
      key = file;
    }
    auto it = resource_meshes.find(key);
    if (key.empty() || it == resource_meshes.end()) {
      std::pair<int, std::string> r{-1, ""};
      try {
        MeshTriangles m;
        if (key.empty())
          throw file_error(path, "node '" + tn.name + "' has mesh = ExtResource(\"" + tn.mesh_ext +
                                     "\"), which the scene does not declare");
        if (!tn.mesh_sub.empty() && !sub)
          throw file_error(path, "node '" + tn.name + "' has mesh = SubResource(\"" + tn.mesh_sub +
                                     "\"), which the scene does not declare");
        if (sub) {
          m = godot_sub_resource_mesh(*sub, path, primitive_texel_size());
        } else {
          if (!input_exists(file)) throw file_error(file, "mesh resource not in the project");
          std::string mext = utf8_string(fs_path(file).extension());
          for (char& c : mext) c = char(std::tolower(static_cast<unsigned char>(c)));
          add_file(file);
          if (mext == ".obj") r.first = obj_geometry(file);  // Godot's OBJ importer's mesh, UV2 from its cache
          else m = godot_mesh_resource_bytes(read_input_text(file, InputKind::kMesh), file, primitive_texel_size());
        }
        if (r.first < 0) {
          const size_t verts = m.positions.size() / 3;
          if (verts == 0 || m.uv.size() != verts * 2) throw file_error(file, "the mesh has no lightmap UV2");
          if (m.normals.size() != verts * 3) m.normals = vertex_normals(m);
          geometry.push_back({std::move(m), file});
          r.first = int(geometry.size() - 1);
        }
      } catch (const Error& e) {
        r.second = std::string(sub ? sub->type + " sub_resource \"" + sub->id + "\": " : "") + e.what();
      }
      if (key.empty()) {
        nodes[size_t(id)].geometry = -1, nodes[size_t(id)].why = r.second;
        return;
      }
      it = resource_meshes.emplace(key, r).first;
    }
    nodes[size_t(id)].geometry = it->second.first;
    nodes[size_t(id)].why = it->second.second;
  }

  // An .obj named as a mesh resource: Godot's "OBJ as Mesh" importer (bakers/godot/godot_obj.h)
  // with generate_lightmap_uv2, its UV2 from NAME.obj.unwrap_cache. Returns the geometry; throws
  // ahd::Error with the reason when there is none.
  int obj_geometry(const std::string& file) {
    const std::string import_file = file + ".import";
    if (input_exists(import_file)) add_file(import_file);
    if (import_param(import_file, "generate_lightmap_uv2") != "true")
      throw file_error(file, "imported without Generate Lightmap UV2 (generate_lightmap_uv2 in " +
                                 utf8_string(fs_path(import_file).filename()) + "): the mesh has no lightmap UVs");
    const auto vec3 = [&](const std::string& key, float fallback, float out[3]) {
      out[0] = out[1] = out[2] = fallback;
      const std::string v = import_param(import_file, key);  // Vector3(x, y, z)
      if (v.rfind("Vector3(", 0) == 0) {
        std::stringstream ss(v.substr(8));
        char comma;
        ss >> out[0] >> comma >> out[1] >> comma >> out[2];
      }
    };
    float scale[3], offset[3];
    vec3("scale_mesh", 1.0f, scale);
    vec3("offset_mesh", 0.0f, offset);
    const GodotObjMesh o = parse_godot_obj_mesh(read_text(file), file, scale, offset);
    UnwrapFile uf;
    uf.path = file, uf.cache_file = file + ".unwrap_cache", uf.gen_uv2 = true;
    if (input_exists(uf.cache_file)) {
      uf.cache = read_godot_unwrap_cache(uf.cache_file);
      add_file(uf.cache_file);
    }
    uf.texel = std::max(0.001f, import_float(import_file, "generate_lightmap_uv2_texel_size", 0.2f));
    MeshGroup g;
    g.scales = {{1.0f, 1.0f, 1.0f}};  // lightmap_unwrap_cached(Transform3D()): the identity
    MeshArrays& a = g.arrays;
    a.name = utf8_string(fs_path(file).stem());
    a.pos = o.positions, a.nrm = o.normals, a.all_uv1 = false, a.all_normals = o.has_normals;
    a.idx.resize(o.indices.size());  // stored so that godot_winding() gives Godot's triangles back
    for (size_t t = 0; t + 2 < o.indices.size(); t += 3)
      a.idx[t] = o.indices[t], a.idx[t + 1] = o.indices[t + 2], a.idx[t + 2] = o.indices[t + 1];
    if (!o.has_normals)
      a.inexact =
          "the file has no normals: Godot generates them (SurfaceTool::generate_normals), which is not "
          "reproduced here";
    if (uf.cache.empty())
      throw file_error(file, "no " + utf8_string(fs_path(uf.cache_file).filename()) + " beside it: reimport it in Godot");
    std::vector<bool> claimed(uf.cache.size(), false);
    exact_entry(uf, &g, &claimed);
    const int geo = group_geometry(uf, &g, claimed);
    if (geo < 0) throw Error(g.why);
    return geo;
  }

  // The project's primitive texel size (project.godot, read once, and a file the result depends on).
  float texel_size = -1;
  float primitive_texel_size() {
    if (texel_size > 0) return texel_size;
    texel_size = kGodotPrimitiveTexelSize;
    const fs::path settings = project / "project.godot";
    if (probe_regular_file(utf8_string(settings))) {
      add_file(utf8_string(settings));
      texel_size = godot_primitive_texel_size(read_text(utf8_string(settings)));
    }
    return texel_size;
  }

  // Area-weighted vertex normals of a mesh given without them.
  static std::vector<float> vertex_normals(const MeshTriangles& m) {
    std::vector<float> n(m.positions.size(), 0.0f);
    for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {
      const uint32_t i[3] = {m.indices[t], m.indices[t + 1], m.indices[t + 2]};
      if (size_t(std::max({i[0], i[1], i[2]})) * 3 + 2 >= m.positions.size()) continue;
      const float* a = &m.positions[i[0] * 3];
      const float* b = &m.positions[i[1] * 3];
      const float* c = &m.positions[i[2] * 3];
      const float u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
      const float f[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
      for (uint32_t k : i)
        for (int d = 0; d < 3; ++d) n[k * 3 + uint32_t(d)] += f[d];
    }
    for (size_t v = 0; v + 2 < n.size(); v += 3) {
      const float l = std::sqrt(n[v] * n[v] + n[v + 1] * n[v + 1] + n[v + 2] * n[v + 2]);
      if (l > 0) n[v] /= l, n[v + 1] /= l, n[v + 2] /= l;
    }
    return n;
  }

  // A .glb/.gltf as Godot imports it: a node named after the file holding the glTF root nodes;
  // meshes get their lightmap UVs from the unwrap cache (light_baking=2) or TEXCOORD_1.
  int mesh_file(const std::string& path, int parent) {
    add_file(path);
    // No JoinIdenticalVertices: the unwrap cache indexes the accessor's vertices as stored. The
    // import reads the file once, checks it as --mesh does (scene/mesh_io.h) and parses those bytes.
    MeshFileReads reads;
    const ImportedScene sc = import_mesh_file(path, kImportTriangulate | kImportValidateDataStructure, &reads);
    const std::string import_file = path + ".import", cache_file = path + ".unwrap_cache";
    const bool gen_uv2 = import_param(import_file, "meshes/light_baking") == "2";
    if (input_exists(import_file)) add_file(import_file);
    std::vector<GodotUnwrapEntry> cache;
    if (gen_uv2 && input_exists(cache_file)) {
      cache = read_godot_unwrap_cache(cache_file);
      add_file(cache_file);
    }
    const int root = add(utf8_string(fs_path(path).stem()), parent);
    // Assimp's root is the glTF scene's only root node, or a synthetic "ROOT" above several.
    const ImportedNode* top = &sc.nodes[0];
    const bool synthetic = top->name == "ROOT" && top->meshes.empty();
    std::vector<std::pair<const ImportedNode*, int>> todo;
    std::vector<std::pair<const ImportedNode*, int>> with_mesh;
    if (synthetic) {
      for (unsigned c : top->children) todo.push_back({&sc.nodes[c], root});
    } else if (gltf_single_root(reads.load(path))) {
      // A file Godot exported (extension GODOT_single_root): its one root node is the scene's root
      // itself, not a child of a node named after the file (modules/gltf/gltf_document.cpp,
      // _generate_scene_node_tree; modules/gltf/structures/gltf_node.cpp leaves it out of paths).
      const Mat4f& m = top->transform;
      nodes[size_t(root)].local = {m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10], m[3], m[7], m[11]};
      if (!top->meshes.empty()) with_mesh.push_back({top, root});
      for (size_t c = top->children.size(); c-- > 0;) todo.push_back({&sc.nodes[top->children[c]], root});
    } else {
      todo.push_back({top, root});
    }
    while (!todo.empty()) {
      const auto [an, p] = todo.back();
      todo.pop_back();
      const int id = add(godot_node_name(an->name), p);
      const Mat4f& m = an->transform;
      nodes[size_t(id)].local = {m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10], m[3], m[7], m[11]};
      if (!an->meshes.empty()) with_mesh.push_back({an, id});
      for (size_t c = an->children.size(); c-- > 0;) todo.push_back({&sc.nodes[an->children[c]], id});
    }
    // Nodes sharing meshes and scale share the geometry (the scale is part of Godot's cache key).
    UnwrapFile uf;
    uf.path = path, uf.cache_file = cache_file, uf.gen_uv2 = gen_uv2, uf.cache = std::move(cache);
    uf.texel = import_float(import_file, "meshes/lightmap_texel_size", 0.2f);
    uf.texel = std::max(0.001f, uf.texel);  // as resource_importer_scene.cpp clamps it
    const float root_scale = import_float(import_file, "nodes/root_scale", 1.0f);
    std::map<std::pair<std::vector<unsigned>, std::array<float, 3>>, size_t> group_of;
    std::vector<MeshGroup> groups;
    for (const auto& [an, id] : with_mesh) {
      MeshGroup g;
      g.meshes = an->meshes;
      node_scales(sc, an, synthetic, root_scale, &g);
      const auto key = std::make_pair(g.meshes, g.scales[0]);
      auto it = group_of.find(key);
      if (it == group_of.end()) {
        it = group_of.emplace(key, groups.size()).first;
        g.arrays = mesh_arrays(sc, g.meshes);
        groups.push_back(std::move(g));
      }
      groups[it->second].nodes.push_back(id);
    }
    assign_groups(uf, groups, gen_uv2);
    return root;
  }

  // A .fbx as Godot's own FBX importer builds it (bakers/godot/godot_fbx.h): a node named after
  // the file holding the file's root nodes; meshes get their lightmap UVs from the unwrap cache
  // (light_baking=2) or the file's second UV set.
  int fbx_file(const std::string& path, int parent) {
    add_file(path);
    const std::string import_file = path + ".import", cache_file = path + ".unwrap_cache";
    if (input_exists(import_file)) add_file(import_file);
    const int root = add(utf8_string(fs_path(path).stem()), parent);
    // fbx/importer = 1 (editor/import/3d/resource_importer_scene.cpp, modules/fbx): the file went
    // through the external FBX2glTF converter, whose output is not reproduced here.
    if (import_param(import_file, "fbx/importer") == "1") {
      nodes[size_t(root)].placeholder = true;
      nodes[size_t(root)].why = path +
                                " is imported through FBX2glTF (fbx/importer = 1), whose conversion is not "
                                "reproduced here: import it with ufbx (the default) in Godot and bake again";
      return root;
    }
    const GodotFbxScene f = read_godot_fbx(path);
    const bool gen_uv2 = import_param(import_file, "meshes/light_baking") == "2";
    UnwrapFile uf;
    uf.path = path, uf.cache_file = cache_file, uf.gen_uv2 = gen_uv2;
    if (gen_uv2 && input_exists(cache_file)) {
      uf.cache = read_godot_unwrap_cache(cache_file);
      add_file(cache_file);
    }
    uf.texel = std::max(0.001f, import_float(import_file, "meshes/lightmap_texel_size", 0.2f));
    const float root_scale = import_float(import_file, "nodes/root_scale", 1.0f);
    std::vector<int> ids(f.nodes.size(), -1);
    std::map<std::pair<std::vector<unsigned>, std::array<float, 3>>, size_t> group_of;
    std::vector<MeshGroup> groups;
    for (size_t i = 0; i < f.nodes.size(); ++i) {
      const GodotFbxNode& n = f.nodes[i];
      const int id = add(n.name, n.parent < 0 ? root : ids[size_t(n.parent)]);
      ids[i] = id;
      const auto& l = n.local;
      nodes[size_t(id)].local = {l[0], l[1], l[2], l[4], l[5], l[6], l[8], l[9], l[10], l[3], l[7], l[11]};
      if (n.mesh < 0) continue;
      MeshGroup g;
      g.meshes = {unsigned(n.mesh)};
      std::vector<Mat4f> chain;
      for (int at = int(i); at >= 0; at = f.nodes[size_t(at)].parent) chain.push_back(f.nodes[size_t(at)].local);
      chain_scales(chain, root_scale, &g);
      const auto key = std::make_pair(g.meshes, g.scales[0]);
      auto it = group_of.find(key);
      if (it == group_of.end()) {
        it = group_of.emplace(key, groups.size()).first;
        const GodotFbxMesh& m = f.meshes[size_t(n.mesh)];
        MeshArrays& a = g.arrays;
        a.name = m.name;
        a.pos = m.positions, a.nrm = m.normals, a.uv1 = m.uv2;
        a.all_uv1 = !m.uv2.empty(), a.all_normals = m.has_normals;
        a.idx.resize(m.indices.size());  // stored so that godot_winding() gives Godot's triangles back
        for (size_t t = 0; t + 2 < m.indices.size(); t += 3)
          a.idx[t] = m.indices[t], a.idx[t + 1] = m.indices[t + 2], a.idx[t + 2] = m.indices[t + 1];
        if (m.polygons)
          a.inexact = "its faces of more than 4 corners are split by ufbx in Godot, which is not reproduced here";
        else if (!m.has_normals)
          a.inexact = "it has no normals in the file, and those ufbx generates for Godot are not reproduced here";
        else if (f.mirrored)
          a.inexact = "the file's axes are left-handed, and ufbx's conversion of them is not reproduced here";
        groups.push_back(std::move(g));
      }
      groups[it->second].nodes.push_back(id);
    }
    assign_groups(uf, groups, gen_uv2);
    return root;
  }

  // What a glTF file's meshes need for their lightmap UVs.
  struct UnwrapFile {
    std::string path, cache_file;
    bool gen_uv2 = false;
    std::vector<GodotUnwrapEntry> cache;
    float texel = 0.2f;
  };
  // The arrays of a node's meshes, concatenated as Godot's importer concatenates a mesh's surfaces.
  struct MeshArrays {
    std::vector<float> pos, nrm, uv1;
    std::vector<uint32_t> idx;  // as the file stores them (glTF winding)
    bool all_uv1 = true, all_normals = true;
    std::string name;
    std::string inexact;  // why Godot's key may not be reproduced for this mesh ("" when it is)
  };
  struct MeshGroup {
    std::vector<unsigned> meshes;
    std::vector<std::array<float, 3>> scales;  // the node's scale as Godot may have computed it (first: ours)
    std::vector<int> nodes;
    MeshArrays arrays;
    int entry = -1;   // the cache entry matched by Godot's key
    std::string why;  // why there is no geometry
  };

  // Every group's geometry from the unwrap cache, given to its nodes: first every mesh whose key is
  // in the cache claims its entry; then the others are matched by their triangles among the
  // entries left.
  void assign_groups(const UnwrapFile& uf, std::vector<MeshGroup>& groups, bool gen_uv2) {
    std::vector<bool> claimed(uf.cache.size(), false);
    if (gen_uv2)
      for (MeshGroup& g : groups) exact_entry(uf, &g, &claimed);
    for (MeshGroup& g : groups) {
      const int geo = group_geometry(uf, &g, claimed);
      for (int id : g.nodes) {
        nodes[size_t(id)].geometry = geo;
        nodes[size_t(id)].why = g.why;
      }
    }
  }

  static float import_float(const std::string& import_file, const std::string& key, float fallback) {
    const std::string v = import_param(import_file, key);
    char* end = nullptr;
    const float f = std::strtof(v.c_str(), &end);
    return v.empty() || !end || *end != '\0' || !std::isfinite(f) ? fallback : f;
  }

  // The scale of `an`'s transform in the scene Godot imports (importer_mesh.cpp keeps only the
  // columns' lengths of the product of the node transforms up to the scene root, whose own
  // transform is the root scale). Two ways to rebuild Godot's float basis from Assimp's matrices:
  // from each node's decomposed rotation and scale (as Godot's glTF importer builds it), and from
  // the matrices as Assimp holds them. The key decides which (if either) Godot computed.
  static void node_scales(const ImportedScene& sc, const ImportedNode* an, bool synthetic, float root_scale,
                          MeshGroup* g) {
    const ImportedNode* top = &sc.nodes[0];
    std::vector<Mat4f> chain;
    for (const ImportedNode* at = an; at && !(synthetic && at == top);
         at = at->parent >= 0 ? &sc.nodes[size_t(at->parent)] : nullptr)
      chain.push_back(at->transform);
    chain_scales(chain, root_scale, g);
  }
  // The same from the node's transform and its parents' (`chain`, the node first).
  static void chain_scales(const std::vector<Mat4f>& chain, float root_scale, MeshGroup* g) {
    float trs[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, mat[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    for (const Mat4f& m : chain) {
      Vec3f s, t;
      std::array<float, 4> q;
      mat4_decompose(m, &s, &q, &t);  // aiMatrix4x4::Decompose
      const float quat[4] = {q[0], q[1], q[2], q[3]}, sc[3] = {s.x, s.y, s.z};
      float b[9];
      godot_basis_from_trs(quat, sc, b);
      godot_basis_mul(b, trs, trs);
      const float r[9] = {m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10]};
      godot_basis_mul(r, mat, mat);
    }
    const float rs[9] = {root_scale, 0, 0, 0, root_scale, 0, 0, 0, root_scale};
    godot_basis_mul(rs, trs, trs);
    godot_basis_mul(rs, mat, mat);
    std::array<float, 3> a, b;
    godot_node_scale(trs, a.data());
    godot_node_scale(mat, b.data());
    g->scales = {a};
    if (b != a) g->scales.push_back(b);
  }

  static MeshArrays mesh_arrays(const ImportedScene& sc, const std::vector<unsigned>& meshes) {
    MeshArrays a;
    a.name = sc.meshes[meshes[0]].name;
    for (unsigned mi : meshes) {
      const ImportedMesh& m = sc.meshes[mi];
      if (!(m.primitive_types & kPrimitiveTriangle)) continue;
      const uint32_t base = uint32_t(a.pos.size() / 3);
      const bool has_uv1 = m.uv_sets >= 2, has_normals = !m.normals.empty();
      a.all_uv1 = a.all_uv1 && has_uv1;
      a.all_normals = a.all_normals && has_normals;
      for (unsigned v = 0; v < m.vertices; ++v) {
        const float* p = &m.positions[size_t(v) * 3];
        a.pos.insert(a.pos.end(), {p[0], p[1], p[2]});
        const float* n = has_normals ? &m.normals[size_t(v) * 3] : nullptr;
        a.nrm.insert(a.nrm.end(), {n ? n[0] : 0.0f, n ? n[1] : 0.0f, n ? n[2] : 0.0f});
        const float* t = has_uv1 ? &m.uv[1][size_t(v) * 2] : nullptr;
        a.uv1.insert(a.uv1.end(), {t ? t[0] : 0.0f, t ? t[1] : 0.0f});
      }
      for (size_t f = 0; f < m.faces(); ++f)
        if (m.face_size(f) == 3)
          for (unsigned k = 0; k < 3; ++k) a.idx.push_back(base + m.face(f)[k]);
    }
    return a;
  }

  static GodotUnwrapKey key_of(const GodotUnwrapEntry& e) {
    GodotUnwrapKey k;
    std::copy(e.hash, e.hash + 16, k.begin());
    return k;
  }

  // Godot's triangles: glTF's a, b, c is Godot's a, c, b (its front faces are clockwise).
  static std::vector<uint32_t> godot_winding(const std::vector<uint32_t>& idx) {
    std::vector<uint32_t> w = idx;
    for (size_t t = 0; t + 2 < w.size(); t += 3) std::swap(w[t + 1], w[t + 2]);
    return w;
  }

  // The entry whose hash is the mesh's key (Godot's own lookup, modules/xatlas_unwrap).
  static void exact_entry(const UnwrapFile& uf, MeshGroup* g, std::vector<bool>* claimed) {
    if (uf.cache.empty() || g->arrays.pos.empty() || !g->arrays.all_normals) return;
    const std::vector<uint32_t> w = godot_winding(g->arrays.idx);
    for (const std::array<float, 3>& s : g->scales) {
      const GodotUnwrapKey key = godot_unwrap_key(g->arrays.pos, g->arrays.nrm, w, s.data(), uf.texel);
      for (size_t e = 0; e < uf.cache.size(); ++e)
        if (std::equal(key.begin(), key.end(), uf.cache[e].hash)) {
          g->entry = int(e);
          (*claimed)[e] = true;
          return;
        }
    }
  }

  // Whether entry `e`'s triangles, through its source vertices, are the mesh's (in Godot's winding
  // and order; the unwrapper may have dropped degenerate ones).
  static bool same_triangles(const GodotUnwrapEntry& e, const std::vector<uint32_t>& w, size_t verts) {
    if (e.source_vertices > verts || e.indices.empty() || e.indices.size() > w.size()) return false;
    size_t at = 0, skipped = 0;
    for (size_t t = 0; t + 2 < e.indices.size(); t += 3) {
      const uint32_t a = e.source_vertex[e.indices[t]], b = e.source_vertex[e.indices[t + 1]],
                     c = e.source_vertex[e.indices[t + 2]];
      while (at + 2 < w.size() && !(w[at] == a && w[at + 1] == b && w[at + 2] == c)) at += 3, ++skipped;
      if (at + 2 >= w.size()) return false;
      at += 3;
    }
    return skipped * 10 <= w.size() / 3;
  }

  // The lightmap geometry of a group's meshes (−1 when it has none: g->why says why).
  int group_geometry(const UnwrapFile& uf, MeshGroup* g, const std::vector<bool>& claimed) {
    const MeshArrays& a = g->arrays;
    const uint32_t verts = uint32_t(a.pos.size() / 3);
    if (verts == 0) {
      g->why = uf.path + ": mesh '" + a.name + "' has no triangles";
      return -1;
    }
    Geometry geo;
    geo.file = uf.path;
    if (uf.gen_uv2 && !uf.cache.empty()) {
      int pick = g->entry;
      if (pick < 0) {
        const std::vector<uint32_t> w = godot_winding(a.idx);  // Godot's winding
        std::vector<size_t> fit;
        for (size_t e = 0; e < uf.cache.size(); ++e)
          if (!claimed[e] && same_triangles(uf.cache[e], w, verts)) fit.push_back(e);
        const std::string mesh = "mesh '" + a.name + "' (" + std::to_string(verts) + " vertices)";
        if (fit.size() == 1) {
          pick = int(fit[0]);
          notes.push_back(
              uf.cache_file + ": " + mesh + " takes entry " + std::to_string(pick + 1) + " of " +
              std::to_string(uf.cache.size()) + " by its triangles, not by Godot's key (its positions or " +
              "normals differ from those the cache was made from, or its node's scale is not reproduced here)");
        } else if (fit.size() > 1) {
          g->why = uf.cache_file + ": " + std::to_string(fit.size()) + " entries fit " + mesh +
                   " by their triangles and none by Godot's key, so which UV2 is its own is unknown; reimport " +
                   uf.path + " in Godot (it rewrites the cache)";
          return -1;
        } else {
          // Godot keeps its entries sorted by key and inserts a new one before the first greater
          // key, so one greater than every key (the first entry's) is never written.
          GodotUnwrapKey last{};
          for (const GodotUnwrapEntry& e : uf.cache) last = std::max(last, key_of(e));
          const GodotUnwrapKey key = godot_unwrap_key(a.pos, a.nrm, w, g->scales[0].data(), uf.texel);
          if (!a.inexact.empty())
            g->why = uf.cache_file + ": no entry fits " + mesh + " by Godot's key or by its triangles: " + a.inexact;
          else if (a.all_normals && key > last)
            g->why = uf.cache_file + " has no entry for " + mesh +
                     ": Godot's importer left it out (an entry whose key sorts " +
                     "after the first one written is dropped, godotengine/godot#122494), so reimporting writes the "
                     "same cache; " +
                     "export the baked scene from the editor as glTF (Scene > Export As > glTF 2.0) and give it with "
                     "--godot-scene";
          else
            g->why = uf.cache_file + " has no entry for " + mesh + ": the cache was written for another version of " +
                     uf.path + "; reimport it in Godot (it rewrites the cache)";
          return -1;
        }
      }
      const GodotUnwrapEntry& e = uf.cache[size_t(pick)];
      for (size_t v = 0; v < e.source_vertex.size(); ++v) {
        const size_t s = e.source_vertex[v];
        geo.mesh.positions.insert(geo.mesh.positions.end(), a.pos.begin() + std::ptrdiff_t(s * 3),
                                  a.pos.begin() + std::ptrdiff_t(s * 3 + 3));
        geo.mesh.normals.insert(geo.mesh.normals.end(), a.nrm.begin() + std::ptrdiff_t(s * 3),
                                a.nrm.begin() + std::ptrdiff_t(s * 3 + 3));
        geo.mesh.uv.insert(geo.mesh.uv.end(), {e.uv2[v * 2], 1.0f - e.uv2[v * 2 + 1]});  // v down → v up
      }
      geo.mesh.indices = e.indices;
    } else if (a.all_uv1) {
      geo.mesh.positions = a.pos;
      geo.mesh.normals = a.nrm;
      geo.mesh.uv = a.uv1;  // Assimp hands glTF UVs over v up already
      geo.mesh.indices = a.idx;
    } else {
      g->why = uf.path + ": mesh '" + a.name + "' has no lightmap UVs (no TEXCOORD_1" +
               std::string(uf.gen_uv2 ? ", no " + uf.cache_file
                                      : ", not imported with meshes/light_baking = Static Lightmaps") +
               ")";
      return -1;
    }
    geometry.push_back(std::move(geo));
    return int(geometry.size() - 1);
  }

  Affine world(int id) const {
    Affine m = kIdentity;
    for (int at = id; at >= 0; at = nodes[size_t(at)].parent) m = compose(nodes[size_t(at)].local, m);
    return m;
  }
};

// The folder res:// names: the nearest folder at or above `file`'s holding project.godot, spelt
// as `file` is (a relative path stays relative, climbing with ".." past its first folder).
fs::path project_root(const fs::path& file) {
  fs::path dir = file.parent_path();
  if (dir.empty()) dir = ".";
  std::error_code ec;
  for (int up = 0; up < 64; ++up) {
    if (probe_input_file(utf8_string(dir / "project.godot"))) return dir;
    const fs::path abs = fs::absolute(dir, ec).lexically_normal();
    if (ec || abs == abs.root_path() || abs.parent_path() == abs) break;
    const fs::path parent = dir.parent_path();
    dir = dir == "." || dir.filename() == ".." || parent.empty() ? (dir / "..").lexically_normal() : parent;
  }
  return file.parent_path().empty() ? fs::path(".")
                                    : file.parent_path();  // no project file: res:// is the file's folder
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
  L.add_file(lmbake);
  out.users = int(data.users.size());
  int no_node = 0, no_mesh = 0, grid = 0;
  std::vector<std::string> left_out;  // instance by instance: which user and why
  const auto unplaced = [&out](const GodotLightmapUser& u, const std::string& node, const std::string& why) {
    GodotUnplacedUser x;
    x.node = node, x.page = u.slice, x.why = why;
    std::copy(u.rect, u.rect + 4, x.rect);
    out.unplaced.push_back(std::move(x));
  };
  for (const GodotLightmapUser& u : data.users) {
    if (u.sub_instance >= 0) {
      ++grid;
      unplaced(u, u.path + " [cell " + std::to_string(u.sub_instance) + "]",
               "a GridMap cell: its MeshLibrary item's mesh and the cell's transform are not read");
      continue;
    }
    const int id = u.path.empty() || u.path[0] == '/' ? -1 : resolve(u.path);
    if (id < 0) {
      ++no_node;
      // The deepest node of the path that is there says why the rest is not (a missing or unread file).
      std::string why = "its node is not in the scene";
      int tries = 0;  // the 32 deepest parents: a path of thousands of steps costs no more
      for (size_t cut = u.path.rfind('/'); cut != std::string::npos && cut > 0 && tries++ < 32;
           cut = u.path.rfind('/', cut - 1)) {
        const int at = resolve(u.path.substr(0, cut));
        if (at < 0) continue;
        const Node& a = L.nodes[size_t(at)];
        if (!a.why.empty()) why = a.why;
        else if (a.placeholder)
          why = "the scene or mesh file instanced at " + u.path.substr(0, cut) + " is missing or not read";
        break;
      }
      unplaced(u, u.path, why);
      continue;
    }
    const Node& n = L.nodes[size_t(id)];
    if (n.geometry < 0) {
      ++no_mesh;
      const std::string why = n.why.empty() ? std::string(n.placeholder ? "its scene or mesh file is not read"
                                                                        : "no mesh with lightmap UVs found on the node")
                                            : n.why;
      left_out.push_back("lightmap user " + u.path + " left out: " + why);
      unplaced(u, u.path, why);
      continue;
    }
    // Each user is a copy of its node's geometry: the copies are bounded in all (scene/mesh_io.h).
    const MeshTriangles& g = L.geometry[size_t(n.geometry)].mesh;
    if (out.scene.mesh.positions.size() / 3 + g.positions.size() / 3 > kMaxSceneVertices ||
        out.scene.mesh.indices.size() + g.indices.size() > kMaxSceneIndices)
      throw file_error(lmbake, "its users place more than " + std::to_string(kMaxSceneVertices) + " vertices or " +
                                   std::to_string(kMaxSceneIndices) + " indices in all (docs/robustness-input.md)");
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
  const size_t kMaxListed = 50;
  for (size_t k = 0; k < left_out.size() && k < kMaxListed; ++k) out.notes.push_back(left_out[k]);
  if (left_out.size() > kMaxListed)
    out.notes.push_back("… and " + std::to_string(left_out.size() - kMaxListed) + " more user(s) left out");
  if (no_mesh) out.notes.push_back(std::to_string(no_mesh) + " lightmap user(s) without a mesh with lightmap UVs here");
  if (grid) out.notes.push_back(std::to_string(grid) + " GridMap cell user(s) not read");
  out.files = L.files;
  for (const std::string& f : out.files) note_input_file(f);  // the depfile and the cache key (files/input_record.h)
  if (out.scene.instances.empty())
    throw file_error(lmbake, "none of its " + std::to_string(data.users.size()) +
                                 " users is a mesh with lightmap UVs in " + from +
                                 (!out.unplaced.empty() ? " (lightmap user " + out.unplaced.front().node +
                                                              " left out: " + out.unplaced.front().why + ")"
                                  : out.notes.empty() ? ""
                                                      : " (" + out.notes.front() + ")"));
  return out;
}

}  // namespace

GodotSceneMeshes load_godot_scene(const std::string& tscn, const std::string& lmbake_override) {
  Loader L;
  L.project = project_root(fs_path(tscn));
  const std::string top_path = utf8_string(fs_path(tscn).lexically_normal());
  const int root = L.scene(top_path, -1, 0);

  // The LightmapGI node of the top scene (its light_data names the .lmbake).
  const GodotTscn& top = L.parsed_scene(top_path);
  int gi = -1;
  std::string lmbake = lmbake_override;
  for (const GodotTscnNode& tn : top.nodes) {
    if (tn.type != "LightmapGI") continue;
    gi = tn.has_parent ? L.find(root, tn.parent == "." ? tn.name : tn.parent + "/" + tn.name) : root;
    if (lmbake.empty() && !tn.light_data.empty())
      if (const GodotTscnExt* e = top.find_ext(tn.light_data)) lmbake = L.resolve(e->path, fs_path(tscn).parent_path(), tscn);
    break;
  }
  if (gi < 0) throw file_error(tscn, "no LightmapGI node: not the scene that was baked (give the scene holding the LightmapGI)");
  if (lmbake.empty()) throw file_error(tscn, "the LightmapGI has no light_data (.lmbake): bake it in Godot first");

  return place_users(L, lmbake, read_godot_lmbake(lmbake), tscn, [&](const std::string& path) { return L.find(gi, path); });
}

// The node-name comparisons the editor-export search may make (about a second): the search tries
// every node as the users' parent, so it grows as nodes × users × path steps.
constexpr uint64_t kMaxPlacementSteps = 200000000;

GodotSceneMeshes load_godot_export(const std::string& gltf, const std::string& lmbake) {
  Loader L;
  L.project = fs::absolute(fs_path(gltf)).parent_path();
  L.mesh_file(utf8_string(fs_path(gltf).lexically_normal()), -1);
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
  // Each user's path split once (the search below tries it from every node).
  std::vector<std::vector<std::string>> user_steps(data.users.size());
  for (size_t k = 0; k < data.users.size(); ++k) {
    const std::string& path = data.users[k].path;
    std::stringstream ss(path.rfind("../", 0) == 0 ? path.substr(3) : path);
    for (std::string step; std::getline(ss, step, '/');)
      if (step != "." && !step.empty()) user_steps[k].push_back(step);
  }
  const auto find_steps = [&L](int at, const std::vector<std::string>& steps) {
    for (size_t k = 0; k < steps.size() && at >= 0; ++k) {
      ++L.steps;
      at = steps[k] == ".." ? L.nodes[size_t(at)].parent : L.child(at, steps[k]);
    }
    return at;
  };
  int best = -1, best_found = 0;
  for (size_t at = 0; at < L.nodes.size(); ++at) {
    if (L.nodes[at].children.empty()) continue;
    int found = 0;
    if (L.steps > kMaxPlacementSteps)
      throw file_error(gltf, "too many nodes (" + std::to_string(L.nodes.size()) + ") and users (" +
                                 std::to_string(data.users.size()) + ", " + lmbake + ") to place the users by name");
    for (const GodotLightmapUser& u : data.users) {
      if (u.sub_instance >= 0 || u.path.empty() || u.path[0] == '/') continue;
      const int id = find_steps(int(at), user_steps[size_t(&u - data.users.data())]);
      found += id >= 0 && L.nodes[size_t(id)].geometry >= 0;
    }
    if (found > best_found) best = int(at), best_found = found;
  }
  if (best < 0)
    throw file_error(gltf, "no node of the .lmbake's users (" + lmbake + ") is a mesh with TEXCOORD_1 here: export the baked "
                               "scene from Godot's editor (Scene > Export As > glTF 2.0) with its lightmap UVs");
  return place_users(L, lmbake, data, gltf, [&](const std::string& path) { return resolve_at(best, path); });
}

namespace {

// The ext_resource ids of `text`'s header whose path, resolved in `project`, is the file `lmbake`
// (canonical paths compared: symlinks and "a/../b" spellings name the same file).
std::vector<std::string> lmbake_ext_ids(const std::string& text, const fs::path& project, const fs::path& dir,
                                        const fs::path& lmbake_canonical) {
  std::vector<std::string> ids;
  std::istringstream in(text);
  std::string line;
  for (int n = 0; std::getline(in, line) && n < 100000; ++n) {
    if (line.rfind("[node", 0) == 0 || line.rfind("[sub_resource", 0) == 0) break;  // ext_resources come first
    if (line.rfind("[ext_resource", 0) != 0 || line.find(".lmbake") == std::string::npos) continue;
    GodotTscn t;
    try {
      t = parse_godot_tscn(line + "\n[node name=\"n\"]\n", "");
    } catch (const Error&) {
      continue;
    }
    if (t.ext.empty()) continue;
    const std::string& res = t.ext[0].path;
    const fs::path file = res.rfind("res://", 0) == 0 ? project / fs_path(res.substr(6)) : dir / fs_path(res);
    std::error_code ec;
    const fs::path c = fs::weakly_canonical(file, ec);
    if (!ec && c == lmbake_canonical) ids.push_back(t.ext[0].id);
  }
  return ids;
}

}  // namespace

std::string find_godot_scene(const std::string& exr) {
  const fs::path p = fs_path(exr);
  const fs::path folder = p.parent_path().empty() ? fs::path(".") : p.parent_path();
  const fs::path lmbake = folder / fs_path(utf8_string(p.stem()) + ".lmbake");
  std::error_code ec;
  // Probes (files/input_record.h): a .lmbake or project.godot appearing later reads the input again.
  if (!probe_regular_file(utf8_string(lmbake))) return "";
  const fs::path want = fs::weakly_canonical(lmbake, ec);
  if (ec) return "";
  // The project: the nearest project.godot at or above the EXR (else the EXR's folder alone).
  const fs::path project = project_root(fs_path(exr));
  const bool has_project = probe_input_file(utf8_string(project / "project.godot"));
  // A bounded walk: no hidden folders (.godot/ holds the editor's imports), no symlinked folders
  // (no loops), no nested projects, at most 12 levels and 20 000 entries.
  std::vector<std::string> found;
  size_t entries = 0;
  const size_t kMaxEntries = 20000;
  const int kMaxDepth = 12;
  auto it = fs::recursive_directory_iterator(has_project ? project : folder,
                                             fs::directory_options::skip_permission_denied, ec);
  for (; !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (++entries > kMaxEntries) break;
    const fs::directory_entry& e = *it;
    const std::string name = utf8_string(e.path().filename());
    std::error_code ec2;
    if (e.is_directory(ec2)) {
      if (!has_project || name.empty() || name[0] == '.' || e.is_symlink(ec2) || it.depth() + 1 > kMaxDepth ||
          fs::exists(e.path() / "project.godot", ec2))
        it.disable_recursion_pending();
      continue;
    }
    if (e.path().extension() != ".tscn" || !e.is_regular_file(ec2) || name[0] == '.') continue;
    std::string text;
    try {
      text = read_input_text(utf8_string(e.path()), InputKind::kSceneText);
    } catch (const Error&) {
      continue;  // swapped for a FIFO, grown past the bound: not a scene to consider
    }
    const std::vector<std::string> ids = lmbake_ext_ids(text, project, e.path().parent_path(), want);
    if (ids.empty()) continue;
    try {  // the LightmapGI's light_data is one of them
      const GodotTscn t = parse_godot_tscn(text, utf8_string(e.path()));
      for (const GodotTscnNode& n : t.nodes)
        if (n.type == "LightmapGI" && std::find(ids.begin(), ids.end(), n.light_data) != ids.end()) {
          found.push_back(Loader::shortest(e.path().lexically_normal()));
          break;
        }
    } catch (const Error&) {}
  }
  std::sort(found.begin(), found.end());
  if (found.size() <= 1) return found.empty() ? "" : found.front();
  std::vector<std::string> beside;
  const fs::path here = fs::weakly_canonical(folder, ec);
  for (const std::string& f : found) {
    const fs::path dir = fs_path(f).parent_path();
    if (fs::weakly_canonical(dir.empty() ? fs::path(".") : dir, ec) == here) beside.push_back(f);
  }
  if (beside.size() == 1) return beside.front();
  std::string list;
  for (const std::string& f : found) list += (list.empty() ? "" : ", ") + f;
  throw file_error(utf8_string(lmbake), std::to_string(found.size()) + " scenes bake it (" + list +
                                        "): name the one to read with --godot-scene");
}

}  // namespace ahd
