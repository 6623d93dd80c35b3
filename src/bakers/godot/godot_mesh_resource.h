// The meshes a Godot scene defines itself or names as resource files, for LightmapGI users whose
// MeshInstance3D has `mesh = SubResource("…")` (a primitive mesh such as BoxMesh with add_uv2, or
// an inline ArrayMesh) or `mesh = ExtResource("…")` (a .tres/.res/.mesh file). The scene reader
// (io/godot_scene.h) routes every such instance here and places what comes back like a glTF mesh.
#pragma once
#include <string>

#include "io/godot_tscn.h"
#include "mesh/lightmap_raster.h"

namespace ahd {

// The mesh of a sub_resource (primitive with add_uv2, inline ArrayMesh) or of an external mesh resource
// (.tres/.res/.mesh), local space, lightmap UV2 v-up. Throws ahd::Error("<source>: <cause>").
MeshTriangles godot_sub_resource_mesh(const GodotTscnSub& sub, const std::string& source);
MeshTriangles godot_mesh_resource_path(const std::string& path, const std::string& source);

}  // namespace ahd
