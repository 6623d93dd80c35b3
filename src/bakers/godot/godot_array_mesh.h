// Godot 4's ArrayMesh resources read without Godot: the triangles of a lightmapped mesh with its
// lightmap UV (UV2), from a mesh inline in a scene (`[sub_resource type="ArrayMesh" …]`, e.g. a
// CSG result baked to a mesh) or from a mesh file (.tres text; .res/.mesh binary, "RSRC").
//
// Facts from Godot's source (read, not copied):
// - scene/resources/mesh.cpp (ArrayMesh::_set_surfaces): `_surfaces` is an array of dictionaries
//   with "format", "primitive", "vertex_count", "vertex_data", "attribute_data", "aabb", optional
//   "uv_scale", "index_data" + "index_count", "skin_data", "lods", "blend_shapes", "material", "name".
// - servers/rendering/rendering_server.h (ArrayType, ArrayFormat): array bits 0..12, custom formats
//   3 bits each from bit 13, flags from bit 25 (2D vertices 25, 8 bone weights 27, compressed
//   attributes 29), the surface format version in bits 35..42 (0: Godot 4.0/4.1, 1: 4.2+).
// - servers/rendering_server.cpp: mesh_surface_make_offsets_from_format (the three streams and
//   their strides), _get_array_from_surface (decoding, compressed positions/normals/UVs relative to
//   aabb/uv_scale), fix_surface_compatibility (the 4.0/4.1 interleaved vertex stream).
// - core/math/vector3.cpp (octahedron_decode), core/math/basis.cpp (set_axis_angle).
// - core/variant/variant_parser.cpp: the text syntax; PackedByteArray as numbers (format=3) or as
//   one base64 string (format=4, Godot 4.3+).
#pragma once
#include <string>

#include "scene/lightmap_raster.h"

namespace ahd {

// `surfaces`: the raw text value of an ArrayMesh's `_surfaces` property as written in a
// .tscn/.tres (from '[' to the matching ']'). The triangles of every surface (primitive 3 =
// triangles; others refused), merged in surface order; positions and normals in the mesh's local
// space, normals decoded the way Godot decodes them (octahedral, 16 bits), empty when no surface
// has normals (zero for a surface without them when another has); `uv` the lightmap UV2, flipped to
// v up (1 − Godot's v). Throws ahd::Error("<source>: <cause>") when a surface has no UV2 ("no
// lightmap UV2: …"), for malformed or inconsistent data (sizes against vertex_count and format,
// indices out of range, an unknown format version). Pure, safe on untrusted input: memory linear
// in the text's size, nesting limited.
MeshTriangles godot_array_mesh_text(const std::string& surfaces, const std::string& source);

// A whole resource file's bytes: text (.tres, `[gd_resource type="ArrayMesh" …]`, the `_surfaces`
// of its `[resource]` section) or binary (.res/.mesh, "RSRC", bakers/godot/godot_lmbake.h). Same result and
// errors as godot_array_mesh_text; also refuses a resource that is not an ArrayMesh.
MeshTriangles godot_mesh_resource_file(const std::string& bytes, const std::string& source);

// The mesh of the `[sub_resource type="ArrayMesh" id="<id>"]` section of a .tscn/.tres text (an
// inline mesh), decoded as godot_array_mesh_text does. Throws when there is no such section.
MeshTriangles godot_text_sub_resource_mesh(const std::string& text, const std::string& id, const std::string& source);

}  // namespace ahd
