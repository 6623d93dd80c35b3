// The meshes a Godot scene defines itself or names as resource files, for LightmapGI users whose
// MeshInstance3D has `mesh = SubResource("…")` (a primitive mesh such as BoxMesh with add_uv2, or
// an inline ArrayMesh) or `mesh = ExtResource("…")` (a .tres/.res/.mesh file). The scene reader
// (bakers/godot/godot_scene.h) routes every such instance here and places what comes back like a
// glTF mesh. The decoders: bakers/godot/godot_primitives.h, bakers/godot/godot_array_mesh.h.
#pragma once
#include <string>

#include "bakers/godot/godot_tscn.h"
#include "scene/lightmap_raster.h"

namespace ahd {

// Godot's default rendering/lightmapping/primitive_meshes/texel_size (world units per texel of a
// primitive's UV2 padding).
inline constexpr float kGodotPrimitiveTexelSize = 0.2f;

// The project's rendering/lightmapping/primitive_meshes/texel_size from the text of its
// project.godot ([rendering] section, key lightmapping/primitive_meshes/texel_size); the default
// when absent or not a positive finite number. Pure, safe on untrusted text.
float godot_primitive_texel_size(const std::string& project_godot);

// The mesh of a sub_resource: a primitive (BoxMesh… with add_uv2 = true) or an inline ArrayMesh,
// local space, lightmap UV2 with v up. `texel_size`: godot_primitive_texel_size of the project.
// Throws ahd::Error("<source>: <cause>") for any other type (named in the message), a primitive
// without add_uv2, malformed data. Pure, safe on untrusted input.
MeshTriangles godot_sub_resource_mesh(const GodotTscnSub& sub, const std::string& source,
                                      float texel_size = kGodotPrimitiveTexelSize);

// The mesh of a resource file's bytes: an ArrayMesh (.tres text, .res/.mesh binary) or a primitive
// saved as .tres ([gd_resource type="BoxMesh"] with its [resource] properties). Same result and
// errors as above. Pure, safe on untrusted input.
MeshTriangles godot_mesh_resource_bytes(const std::string& bytes, const std::string& source,
                                        float texel_size = kGodotPrimitiveTexelSize);

}  // namespace ahd
