// Routing a Godot mesh resource to its decoder: primitives (godot_primitives.cpp), ArrayMesh
// (godot_array_mesh.cpp). The few lines of text parsing here read only what routing needs (a
// .tres header's type, a primitive's one-line properties, one project setting).
#include "bakers/godot/godot_mesh_resource.h"

#include <cmath>
#include <cstdlib>
#include <map>

#include "bakers/godot/godot_array_mesh.h"
#include "bakers/godot/godot_primitives.h"
#include "core/error.h"

namespace ahd {
namespace {

std::string trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") + 1 - b);
}

// Calls f(section, key, value) for every single-line `key = value` of a Godot text file (.tres,
// project.godot); `section` is the last `[...]` header's first word (e.g. "resource", "rendering").
template <class F>
void each_line_property(const std::string& text, F f) {
  std::string section;
  size_t pos = 0;
  while (pos < text.size()) {
    size_t eol = text.find('\n', pos);
    if (eol == std::string::npos) eol = text.size();
    const std::string line = trim(text.substr(pos, eol - pos));
    pos = eol + 1;
    if (line.empty() || line[0] == ';') continue;
    if (line[0] == '[') {
      const size_t e = line.find_first_of(" ]", 1);
      section = line.substr(1, (e == std::string::npos ? line.size() : e) - 1);
      continue;
    }
    const size_t eq = line.find('=');
    if (eq != std::string::npos) f(section, trim(line.substr(0, eq)), trim(line.substr(eq + 1)));
  }
}

// `type="X"` of a text resource's [gd_resource …] header, "" when there is none.
std::string text_resource_type(const std::string& text) {
  const size_t h = text.find("[gd_resource");
  if (h == std::string::npos || text.find_first_not_of(" \t\r\n") != h) return "";
  const size_t end = text.find(']', h);
  const size_t t = text.find("type=\"", h);
  if (t == std::string::npos || t > end) return "";
  const size_t q = text.find('"', t + 6);
  return q == std::string::npos || q > end ? "" : text.substr(t + 6, q - t - 6);
}

}  // namespace

float godot_primitive_texel_size(const std::string& project_godot) {
  float size = kGodotPrimitiveTexelSize;
  each_line_property(project_godot, [&](const std::string& section, const std::string& key, const std::string& value) {
    if (section != "rendering" || key != "lightmapping/primitive_meshes/texel_size") return;
    char* end = nullptr;
    const double v = std::strtod(value.c_str(), &end);
    if (end != value.c_str() && std::isfinite(v) && v > 0 && v < 1e6) size = float(v);
  });
  return size;
}

MeshTriangles godot_sub_resource_mesh(const GodotTscnSub& sub, const std::string& source, float texel_size) {
  if (is_godot_primitive_mesh(sub.type)) return godot_primitive_mesh(sub.type, sub.props, source, texel_size);
  if (sub.type == "ArrayMesh") {
    const auto s = sub.props.find("_surfaces");
    if (s == sub.props.end()) throw file_error(source, "the ArrayMesh has no _surfaces property");
    return godot_array_mesh_text(s->second, source);
  }
  // TextMesh (scene/resources/3d/primitive_meshes.cpp): its triangles are the glyph outlines Godot's
  // TextServer draws from the font file, which cannot be reproduced outside Godot.
  throw file_error(source, (sub.type.empty() ? std::string("an untyped mesh") : sub.type) +
                               " is not a mesh with lightmap UV2 that ahdpack reads (primitive meshes with "
                               "add_uv2, ArrayMesh)" +
                               (sub.type == "TextMesh" ? ": its glyphs are drawn by Godot's text server from the font, "
                                                         "which is not reproduced outside Godot"
                                                       : ""));
}

MeshTriangles godot_mesh_resource_bytes(const std::string& bytes, const std::string& source, float texel_size) {
  const std::string type = text_resource_type(bytes);
  if (!is_godot_primitive_mesh(type)) return godot_mesh_resource_file(bytes, source);
  std::map<std::string, std::string> props;
  each_line_property(bytes, [&](const std::string& section, const std::string& key, const std::string& value) {
    if (section == "resource") props[key] = value;
  });
  return godot_primitive_mesh(type, props, source, texel_size);
}

}  // namespace ahd
