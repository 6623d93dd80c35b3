// Godot's cache of the lightmap UVs (UV2) its importer generates for meshes imported with
// meshes/light_baking = "Static Lightmaps" (NAME.glb.unwrap_cache beside the source file), read
// without Godot. Facts from Godot's modules/xatlas_unwrap (the cache layout) and
// scene/resources/importer_mesh.cpp (lightmap_unwrap_cached: how a mesh is rebuilt from it).
//
// Layout (little-endian int32/float32): the entry count, then per entry: a 16-byte MD5 of the
// unwrap's input, the atlas size hint (x, y), the new vertex count V, V source-vertex indices
// ("xref": which vertex of the mesh's surfaces, concatenated in order, each new vertex copies),
// V UV2 pairs (0..1 of the mesh's own chart, v down), the index count I and I indices into the
// new vertices (triangles).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ahd {

struct GodotUnwrapEntry {
  uint8_t hash[16] = {};
  int size_hint[2] = {0, 0};
  std::vector<uint32_t> source_vertex;  // per new vertex
  std::vector<float> uv2;               // 2 per new vertex, v down
  std::vector<uint32_t> indices;        // 3 per triangle, into the new vertices
  uint32_t source_vertices = 0;         // 1 + the largest source index (0 when empty)
};

// Pure, safe on untrusted input: counts are checked against the bytes left before allocation,
// indices against the vertex count. Throws ahd::Error("<source>: <cause>") for a truncated or
// inconsistent cache, or bytes after the last entry.
std::vector<GodotUnwrapEntry> parse_godot_unwrap_cache(const uint8_t* data, size_t size, const std::string& source);

// Reads the file and parses it (ahd::Error "<path>: file not found" when missing).
std::vector<GodotUnwrapEntry> read_godot_unwrap_cache(const std::string& path);

}  // namespace ahd
