// Godot's LightmapGIData as saved by the editor (NAME.lmbake: Godot's binary resource format,
// "RSRC"), read without Godot: which nodes were baked into the lightmap (each user's node path,
// relative to the LightmapGI node), their atlas page (slice) and UV rectangle.
//
// Facts from Godot's core/io/resource_format_binary.cpp (header, string table, external and
// internal resources, the variant encoding) and scene/3d/lightmap_gi.cpp (user_data: a flat array
// of (NodePath, Rect2 uv_scale, int slice_index, int sub_instance) per user; the mesh samples the
// atlas at uv_scale.position + uv2 · uv_scale.size, v down like every Godot UV).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace ahd {

struct GodotLightmapUser {
  std::string path;       // NodePath as stored, e.g. "../Props/chair/Chair" (relative to the LightmapGI node)
  double rect[4] = {0, 0, 1, 1};  // uv_scale: x, y, width, height (atlas fraction, v down)
  int slice = 0;          // atlas page
  int sub_instance = -1;  // GridMap cell (−1 for a MeshInstance3D)
};

struct GodotLightmapData {
  int engine_major = 0, engine_minor = 0, format = 0;
  std::string type;                     // "LightmapGIData"
  bool uses_spherical_harmonics = false;
  bool has_packed_directional = false;  // the property exists (Godot 4.4+)
  bool packed_directional = false;
  std::vector<std::string> external;    // external resources' paths (res://…), e.g. the lightmap texture
  std::vector<GodotLightmapUser> users;
};

// A value of Godot's binary resource format, as far as readers need it (the format's own variant
// tags, resource_format_binary.cpp); other values are bounds-checked and skipped.
struct GodotBinaryValue {
  uint32_t tag = 1;                     // the format's tag: 1 nil, 2 bool, 3 int, 40 int64, 15 AABB, 26 Dictionary…
  int64_t i64 = 0;                      // bool, int, int64
  double num[6] = {0, 0, 0, 0, 0, 0};   // bool/int/float in num[0]; Rect2/Vector4 x, y, z|w, w|h; AABB position, size
  std::string text;                     // String, StringName, NodePath ("a/b/c", "/" prefix when absolute)
  std::vector<GodotBinaryValue> items;  // Array; Dictionary as key, value, key, value…
  const uint8_t* bytes = nullptr;       // PackedByteArray: a view into the parsed buffer
  size_t byte_count = 0;
};

// The main (last) resource of a Godot binary resource file (.res, .mesh: "RSRC", formats 3..6).
struct GodotBinaryResource {
  int engine_major = 0, engine_minor = 0, format = 0;
  std::string type;  // e.g. "ArrayMesh"
  std::vector<std::pair<std::string, GodotBinaryValue>> properties;
};

// Parses the header, string table and the main resource's properties. Pure, safe on untrusted
// input (the bounds of parse_godot_lmbake); byte views point into `data`, which must outlive the
// result. Throws ahd::Error("<source>: <cause>") for a file that is not an uncompressed
// little-endian binary resource of format 3..6 or is truncated/inconsistent.
GodotBinaryResource parse_godot_binary_resource(const uint8_t* data, size_t size, const std::string& source);

// Parses the bytes of a .lmbake. Pure, safe on untrusted input: every count is bounded by the bytes
// left before anything is allocated, nesting is limited, offsets are checked. Throws
// ahd::Error("<source>: <cause>") for a file that is not a Godot binary resource, a format it does
// not read (big-endian, format version other than 3..6), a truncated or inconsistent file, or a
// user_data array that is not (NodePath, Rect2, int, int) tuples.
GodotLightmapData parse_godot_lmbake(const uint8_t* data, size_t size, const std::string& source);

// Reads the file and parses it (ahd::Error "<path>: file not found" when missing).
GodotLightmapData read_godot_lmbake(const std::string& path);

}  // namespace ahd
