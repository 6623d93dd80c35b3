#include "scene/gltf_precheck.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "core/error.h"
#include "core/json_depth.h"
#include "files/input_file.h"
#include "scene/mesh_io.h"
#include "files/utf8_path.h"

namespace ahd {
namespace fs = std::filesystem;

namespace {

uint32_t rd32(const std::vector<uint8_t>& b, size_t at) {
  return uint32_t(b[at]) | uint32_t(b[at + 1]) << 8 | uint32_t(b[at + 2]) << 16 | uint32_t(b[at + 3]) << 24;
}


// Bytes a base64 data: URI decodes to (an upper bound is enough: padding is not subtracted).
uint64_t data_uri_bytes(const std::string& uri) {
  const size_t comma = uri.find(',');
  if (comma == std::string::npos) return 0;
  return uint64_t(uri.size() - comma - 1) / 4 * 3 + 3;
}

}  // namespace

void check_gltf_structure(const std::string& path) {
  std::string ext = utf8_string(fs_path(path).extension());
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".gltf" && ext != ".glb") return;
  const std::vector<uint8_t> bytes = read_input_bytes(path, InputKind::kMesh);
  check_gltf_bytes(path, bytes, [](const std::string& f) -> int64_t {
    std::error_code ec;
    if (!fs::is_regular_file(fs_path(f), ec)) return -1;
    const auto n = fs::file_size(fs_path(f), ec);
    return ec ? -1 : int64_t(n);
  });
}

void check_gltf_bytes(const std::string& path, const std::vector<uint8_t>& bytes,
                      const std::function<int64_t(const std::string&)>& buffer_bytes) {
  std::string ext = utf8_string(fs_path(path).extension());
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".gltf" && ext != ".glb") return;
  const char* json_text = reinterpret_cast<const char*>(bytes.data());
  size_t json_size = bytes.size();
  uint64_t bin_bytes = 0;
  bool glb = false;
  if (ext == ".glb" || (bytes.size() >= 4 && std::string(json_text, 4) == "glTF")) {
    // GLB: 12-byte header, then chunks (length, type, data); JSON first, BIN optional second.
    if (bytes.size() < 20 || std::string(json_text, 4) != "glTF") throw file_error(path, "not a GLB file (no glTF header)");
    const uint64_t len0 = rd32(bytes, 12);
    if (rd32(bytes, 16) != 0x4E4F534Au || 20 + len0 > bytes.size()) throw file_error(path, "GLB JSON chunk is truncated");
    json_text += 20;
    json_size = size_t(len0);
    const uint64_t at = 20 + ((len0 + 3) & ~uint64_t(3));
    if (at + 8 <= bytes.size() && rd32(bytes, size_t(at) + 4) == 0x004E4942u)
      bin_bytes = std::min<uint64_t>(rd32(bytes, size_t(at)), bytes.size() - at - 8);
    glb = true;
  }
  if (json_nesting_depth(json_text, json_size, kMaxGltfJsonDepth) > kMaxGltfJsonDepth)
    throw file_error(path, "JSON nested more than " + std::to_string(kMaxGltfJsonDepth) + " levels deep");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(json_text, json_text + json_size);
  } catch (const std::exception&) {
    return;  // not JSON: Assimp's own message says why
  }
  if (!j.is_object()) return;

  // Buffers: byteLength against the bytes behind them.
  if (j.contains("buffers") && j["buffers"].is_array()) {
    size_t index = 0;
    for (const auto& b : j["buffers"]) {
      const std::string which = "buffer " + std::to_string(index++);
      if (!b.is_object() || !b.contains("byteLength") || !b["byteLength"].is_number_unsigned()) continue;
      const uint64_t claimed = b["byteLength"].get<uint64_t>();
      uint64_t have = 0;
      if (b.contains("uri") && b["uri"].is_string()) {
        const std::string uri = b["uri"].get<std::string>();
        if (uri.rfind("data:", 0) == 0) {
          have = data_uri_bytes(uri);
        } else {
          const int64_t n = buffer_bytes(utf8_string(fs_path(path).parent_path() / fs_path(uri)));
          if (n < 0) continue;  // missing: Assimp names it
          have = uint64_t(n);
        }
      } else if (glb) {
        have = bin_bytes;
      } else {
        continue;
      }
      if (claimed > have)
        throw file_error(path, which + " claims " + std::to_string(claimed) + " bytes (byteLength) but its data has " +
                                   std::to_string(have));
    }
  }

  // Accessors: elements bounded by the input's bytes (a sparse accessor needs no buffer view, so
  // its count alone would size Assimp's allocation), sparse counts within the accessor.
  uint64_t input_bytes = bytes.size();
  if (j.contains("buffers") && j["buffers"].is_array())
    for (const auto& b : j["buffers"])
      if (b.is_object() && b.contains("byteLength") && b["byteLength"].is_number_unsigned())
        input_bytes += std::min<uint64_t>(b["byteLength"].get<uint64_t>(), uint64_t(1) << 40);
  const uint64_t max_accessor_bytes = 16 * input_bytes + (uint64_t(1) << 20);
  std::vector<uint64_t> accessor_count;
  if (j.contains("accessors") && j["accessors"].is_array()) {
    size_t index = 0;
    for (const auto& a : j["accessors"]) {
      const std::string which = "accessor " + std::to_string(index++);
      uint64_t count = 0;
      if (a.is_object() && a.contains("count") && a["count"].is_number_unsigned()) count = a["count"].get<uint64_t>();
      accessor_count.push_back(count);
      if (!a.is_object()) continue;
      uint64_t component = 4, components = 1;
      if (a.contains("componentType") && a["componentType"].is_number_integer()) {
        const int64_t t = a["componentType"].get<int64_t>();
        component = t == 5120 || t == 5121 ? 1 : t == 5122 || t == 5123 ? 2 : 4;
      }
      if (a.contains("type") && a["type"].is_string()) {
        const std::string t = a["type"].get<std::string>();
        components = t == "VEC2" ? 2 : t == "VEC3" ? 3 : t == "VEC4" || t == "MAT2" ? 4 : t == "MAT3" ? 9 : t == "MAT4" ? 16 : 1;
      }
      if (count > max_accessor_bytes / (component * components))
        throw file_error(path, which + " has " + std::to_string(count) + " elements, more than the file's " +
                                   std::to_string(input_bytes) + " bytes can describe");
      if (a.contains("sparse") && a["sparse"].is_object()) {
        const auto& sp = a["sparse"];
        const uint64_t n = sp.contains("count") && sp["count"].is_number_unsigned() ? sp["count"].get<uint64_t>() : 0;
        if (n == 0 || n > count)
          throw file_error(path, which + ": sparse count " + std::to_string(n) + " is not within its " +
                                     std::to_string(count) + " elements");
      }
    }
  }
  // Instancing: every node holding a mesh is a copy of its primitives' vertices and indices.
  if (j.contains("meshes") && j["meshes"].is_array() && j.contains("nodes") && j["nodes"].is_array()) {
    std::vector<uint64_t> mesh_vertices, mesh_indices;
    const auto count_of = [&](const nlohmann::json& ref) -> uint64_t {
      if (!ref.is_number_unsigned() || ref.get<uint64_t>() >= accessor_count.size()) return 0;
      return accessor_count[size_t(ref.get<uint64_t>())];
    };
    for (const auto& m : j["meshes"]) {
      uint64_t v = 0, i = 0;
      if (m.is_object() && m.contains("primitives") && m["primitives"].is_array())
        for (const auto& p : m["primitives"]) {
          if (!p.is_object()) continue;
          if (p.contains("attributes") && p["attributes"].is_object() && p["attributes"].contains("POSITION"))
            v += count_of(p["attributes"]["POSITION"]);
          if (p.contains("indices")) i += count_of(p["indices"]);
        }
      mesh_vertices.push_back(v), mesh_indices.push_back(i);
    }
    uint64_t vertices = 0, indices = 0;
    for (const auto& n : j["nodes"]) {
      if (!n.is_object() || !n.contains("mesh") || !n["mesh"].is_number_unsigned()) continue;
      const uint64_t m = n["mesh"].get<uint64_t>();
      if (m >= mesh_vertices.size()) continue;  // Assimp names it
      vertices += mesh_vertices[size_t(m)], indices += mesh_indices[size_t(m)];
      if (vertices > kMaxSceneVertices || indices > kMaxSceneIndices)
        throw file_error(path, "its nodes instance more than " + std::to_string(kMaxSceneVertices) + " vertices or " +
                                   std::to_string(kMaxSceneIndices) + " indices in all (docs/robustness-input.md)");
    }
  }

  // Nodes: children indices in range, no cycle, depth bounded — with an explicit stack.
  if (!j.contains("nodes") || !j["nodes"].is_array()) return;
  const auto& nodes = j["nodes"];
  const size_t n = nodes.size();
  std::vector<std::vector<size_t>> children(n);
  std::vector<uint32_t> parents(n, 0);
  for (size_t i = 0; i < n; ++i) {
    if (!nodes[i].is_object() || !nodes[i].contains("children") || !nodes[i]["children"].is_array()) continue;
    for (const auto& c : nodes[i]["children"]) {
      if (!c.is_number_unsigned() || c.get<uint64_t>() >= n)
        throw file_error(path, "node " + std::to_string(i) + " has a child index out of range (" + c.dump() + ", " +
                                   std::to_string(n) + " nodes)");
      const size_t k = size_t(c.get<uint64_t>());
      children[i].push_back(k);
      if (++parents[k] > 1) throw file_error(path, "node " + std::to_string(k) + " has more than one parent");
    }
  }
  std::vector<size_t> depth(n, 0);
  std::vector<size_t> stack;
  size_t reached = 0;
  for (size_t r = 0; r < n; ++r) {
    if (parents[r] != 0) continue;
    depth[r] = 1;
    stack.push_back(r);
    while (!stack.empty()) {
      const size_t i = stack.back();
      stack.pop_back();
      ++reached;
      if (depth[i] > kMaxGltfNodeDepth)
        throw file_error(path, "node hierarchy deeper than " + std::to_string(kMaxGltfNodeDepth) + " levels");
      for (size_t k : children[i]) {
        depth[k] = depth[i] + 1;
        stack.push_back(k);
      }
    }
  }
  // Every node has at most one parent, so nodes not reached from a root lie on a cycle.
  if (reached != n) throw file_error(path, "node hierarchy has a cycle");
}

}  // namespace ahd
