// Writing a placed scene as glTF 2.0 binary (.glb): one node and one mesh per lightmapped
// instance, positions and normals in world space, the lightmap UVs in atlas space. Our own small
// writer (nlohmann json + a little-endian BIN chunk): same meshes, same bytes.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace ahd {

struct GltfInstanceMesh {
  std::string name;                 // the node's name (the instance's node path)
  std::vector<float> positions;     // 3 per vertex, world space
  std::vector<float> normals;       // 3 per vertex (unit; written as NORMAL), or empty
  std::vector<float> uv0, uv1;      // 2 per vertex, glTF convention (v down); either may be empty
  std::vector<uint32_t> indices;    // 3 per triangle
  nlohmann::json extras = nlohmann::json::object();  // the node's "extras"
};

// The .glb bytes: a scene whose root nodes are `meshes` in order (identity transforms), with
// `scene_extras` as the scene's "extras" and `generator` as asset.generator. Accessors carry
// POSITION's min/max (glTF requires them). Throws ahd::Error for inconsistent buffers (a count
// that is not 3/2 per vertex, an index out of range) or a buffer past glTF's 4 GiB.
std::vector<uint8_t> write_glb(const std::vector<GltfInstanceMesh>& meshes, const nlohmann::json& scene_extras,
                               const std::string& generator);

}  // namespace ahd
