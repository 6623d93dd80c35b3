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

// Parses the bytes of a .lmbake. Pure, safe on untrusted input: every count is bounded by the bytes
// left before anything is allocated, nesting is limited, offsets are checked. Throws
// ahd::Error("<source>: <cause>") for a file that is not a Godot binary resource, a format it does
// not read (big-endian, format version other than 3..6), a truncated or inconsistent file, or a
// user_data array that is not (NodePath, Rect2, int, int) tuples.
GodotLightmapData parse_godot_lmbake(const uint8_t* data, size_t size, const std::string& source);

// Reads the file and parses it (ahd::Error "<path>: file not found" when missing).
GodotLightmapData read_godot_lmbake(const std::string& path);

}  // namespace ahd
