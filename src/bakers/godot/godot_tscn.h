// Godot's text scene format (.tscn, format 3), the parts that place meshes: external resources
// (a nested scene or a mesh file, by id), nodes (name, parent path, an instanced scene, the local
// `transform = Transform3D(…)`) and a LightmapGI's `light_data`. Facts from Godot's
// scene/resources/resource_format_text.cpp and core/variant/variant_parser.cpp: Transform3D(…)
// lists the basis by rows, then the origin; a node's `parent` is "." for the root's children and a
// path from the root otherwise; the first node (no parent) is the root; a node whose parent path
// leads into an instanced scene and whose name exists there overrides that node's properties.
//
// Older spellings read alike (variant_parser.cpp tokenises, so spaces between tokens are free):
// format 2 (Godot 3.x) and the 4.0 pre-releases write `ExtResource( 1 )`, `ExtResource( "1_a" )`,
// `Transform( … )` / `Transform3D( … )` with spaces, and ids as bare integers.
//
// Sub-resources (`[sub_resource type="T" id="ID"]`, meshes defined inside the scene) are kept as
// text: their type, id and each property's raw value (a multi-line value such as
// `_surfaces = [{ … }]` whole, its line breaks kept) for the mesh readers to decode.
#pragma once
#include <map>
#include <string>
#include <vector>

namespace ahd {

struct GodotTscnExt {
  std::string id, type, path;  // path as written ("res://…")
};

struct GodotTscnSub {
  std::string id, type;
  std::map<std::string, std::string> props;  // property name -> raw value text as written
  int line = 0;                              // of the section header (for messages)
};

struct GodotTscnNode {
  std::string name, type;
  std::string parent;        // "" for the root, "." for its children, "A/B" below
  bool has_parent = false;
  std::string instance;      // ext_resource id of an instanced scene, or ""
  bool has_transform = false;
  double transform[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};  // basis rows (3×3), then origin
  std::string light_data;    // ext_resource id of `light_data = ExtResource("…")`, or ""
  // `mesh = ExtResource("…")` (a .tres/.res/.mesh file) or `mesh = SubResource("…")` (defined in
  // this file): the id in one of them, "" otherwise. Read on any node; LightmapGI bakes the mesh
  // of a MeshInstance3D (a CSGMesh3D's `mesh` is CSG input, never a lightmap user).
  std::string mesh_ext, mesh_sub;
};

struct GodotTscn {
  int format = 0;  // `format=` of the [gd_scene …] header (2: Godot 3.x, 3: Godot 4), 0 when absent
  std::vector<GodotTscnExt> ext;
  std::vector<GodotTscnSub> sub;
  std::vector<GodotTscnNode> nodes;
  const GodotTscnExt* find_ext(const std::string& id) const;
  const GodotTscnSub* find_sub(const std::string& id) const;
};

// `Name("id")`, `Name( "id" )` or `Name( 12 )` -> the id; "" when `value` is not that form.
std::string godot_resource_ref(const std::string& value, const std::string& name);

// Pure, safe on untrusted text (no recursion, quoted values and multi-line strings skipped; a
// multi-line value is at most 64 MiB). Throws ahd::Error("<source>: line N: <cause>") for a
// malformed section header, a transform that is not 12 finite numbers, an `instance=` that is
// not an ExtResource, a value left open at the end of the file, or a file without a node.
GodotTscn parse_godot_tscn(const std::string& text, const std::string& source);

}  // namespace ahd
