// Godot's text scene format (.tscn, format 3), the parts that place meshes: external resources
// (a nested scene or a mesh file, by id), nodes (name, parent path, an instanced scene, the local
// `transform = Transform3D(…)`) and a LightmapGI's `light_data`. Facts from Godot's
// scene/resources/resource_format_text.cpp and core/variant/variant_parser.cpp: Transform3D(…)
// lists the basis by rows, then the origin; a node's `parent` is "." for the root's children and a
// path from the root otherwise; the first node (no parent) is the root; a node whose parent path
// leads into an instanced scene and whose name exists there overrides that node's properties.
#pragma once
#include <string>
#include <vector>

namespace ahd {

struct GodotTscnExt {
  std::string id, type, path;  // path as written ("res://…")
};

struct GodotTscnNode {
  std::string name, type;
  std::string parent;        // "" for the root, "." for its children, "A/B" below
  bool has_parent = false;
  std::string instance;      // ext_resource id of an instanced scene, or ""
  bool has_transform = false;
  double transform[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};  // basis rows (3×3), then origin
  std::string light_data;    // ext_resource id of `light_data = ExtResource("…")`, or ""
};

struct GodotTscn {
  std::vector<GodotTscnExt> ext;
  std::vector<GodotTscnNode> nodes;
  const GodotTscnExt* find_ext(const std::string& id) const;
};

// Pure, safe on untrusted text (no recursion, quoted values and multi-line strings skipped).
// Throws ahd::Error("<source>: line N: <cause>") for a malformed section header, a transform
// that is not 12 finite numbers, or a file without a node.
GodotTscn parse_godot_tscn(const std::string& text, const std::string& source);

}  // namespace ahd
