#include "scene/gltf_write.h"

#include <algorithm>
#include <cstring>
#include <limits>

#include "core/error.h"

namespace ahd {

using nlohmann::json;

namespace {

constexpr int kFloat = 5126, kUint = 5125;             // glTF componentType
constexpr int kArrayBuffer = 34962, kElementBuffer = 34963;  // bufferView target

struct Writer {
  std::vector<uint8_t> bin;
  json views = json::array(), accessors = json::array();

  // Appends `data` (4-byte aligned) as one buffer view and one accessor; the accessor's index.
  template <class T>
  int add(const std::vector<T>& data, int components, int component_type, int target, const char* type, bool minmax) {
    const size_t offset = bin.size();
    bin.resize(offset + data.size() * sizeof(T));
    if (!data.empty()) std::memcpy(bin.data() + offset, data.data(), data.size() * sizeof(T));
    while (bin.size() % 4) bin.push_back(0);
    views.push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", data.size() * sizeof(T)}, {"target", target}});
    json acc = {{"bufferView", views.size() - 1},
                {"componentType", component_type},
                {"count", data.size() / size_t(components)},
                {"type", type}};
    if (minmax) {
      std::vector<double> lo(size_t(components), std::numeric_limits<double>::infinity()),
          hi(size_t(components), -std::numeric_limits<double>::infinity());
      for (size_t i = 0; i < data.size(); ++i) {
        const size_t c = i % size_t(components);
        lo[c] = std::min(lo[c], double(data[i])), hi[c] = std::max(hi[c], double(data[i]));
      }
      acc["min"] = lo, acc["max"] = hi;
    }
    accessors.push_back(acc);
    return int(accessors.size() - 1);
  }
};

void put_u32(std::vector<uint8_t>* out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out->push_back(uint8_t(v >> (8 * i)));
}

}  // namespace

std::vector<uint8_t> write_glb(const std::vector<GltfInstanceMesh>& meshes, const json& scene_extras,
                               const std::string& generator) {
  Writer w;
  json nodes = json::array(), gmeshes = json::array(), roots = json::array();
  for (const GltfInstanceMesh& m : meshes) {
    const size_t verts = m.positions.size() / 3;
    if (m.positions.size() % 3 || m.indices.size() % 3 || (!m.normals.empty() && m.normals.size() != verts * 3) ||
        (!m.uv0.empty() && m.uv0.size() != verts * 2) || (!m.uv1.empty() && m.uv1.size() != verts * 2))
      throw Error("glTF writer: inconsistent buffers for " + m.name);
    for (uint32_t i : m.indices)
      if (i >= verts) throw Error("glTF writer: index out of range in " + m.name);
    json attrs = {{"POSITION", w.add(m.positions, 3, kFloat, kArrayBuffer, "VEC3", true)}};
    if (!m.normals.empty()) attrs["NORMAL"] = w.add(m.normals, 3, kFloat, kArrayBuffer, "VEC3", false);
    if (!m.uv0.empty()) attrs["TEXCOORD_0"] = w.add(m.uv0, 2, kFloat, kArrayBuffer, "VEC2", false);
    if (!m.uv1.empty()) attrs["TEXCOORD_1"] = w.add(m.uv1, 2, kFloat, kArrayBuffer, "VEC2", false);
    const int ind = w.add(m.indices, 1, kUint, kElementBuffer, "SCALAR", false);
    gmeshes.push_back({{"name", m.name}, {"primitives", json::array({{{"attributes", attrs}, {"indices", ind}, {"mode", 4}}})}});
    json node = {{"name", m.name}, {"mesh", gmeshes.size() - 1}};
    if (!m.extras.empty()) node["extras"] = m.extras;
    nodes.push_back(node);
    roots.push_back(nodes.size() - 1);
  }
  if (w.bin.size() > 0xFFFFFFF0u) throw Error("glTF writer: the scene's buffer passes glTF's 4 GiB");
  json scene = {{"nodes", roots}};
  if (!scene_extras.empty()) scene["extras"] = scene_extras;
  json j = {{"asset", {{"version", "2.0"}, {"generator", generator}}},
            {"scene", 0},
            {"scenes", json::array({scene})},
            {"nodes", nodes},
            {"meshes", gmeshes},
            {"accessors", w.accessors},
            {"bufferViews", w.views},
            {"buffers", json::array({{{"byteLength", w.bin.size()}}})}};
  std::string text = j.dump();
  while (text.size() % 4) text.push_back(' ');
  std::vector<uint8_t> out;
  put_u32(&out, 0x46546C67u);  // "glTF"
  put_u32(&out, 2);
  put_u32(&out, uint32_t(12 + 8 + text.size() + 8 + w.bin.size()));
  put_u32(&out, uint32_t(text.size()));
  put_u32(&out, 0x4E4F534Au);  // "JSON"
  out.insert(out.end(), text.begin(), text.end());
  put_u32(&out, uint32_t(w.bin.size()));
  put_u32(&out, 0x004E4942u);  // "BIN\0"
  out.insert(out.end(), w.bin.begin(), w.bin.end());
  return out;
}

}  // namespace ahd
