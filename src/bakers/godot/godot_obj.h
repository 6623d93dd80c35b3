// An .obj file as Godot's "OBJ as Mesh" importer (wavefront_obj, the default for .obj) builds its
// one mesh, so that the mesh finds its entry of NAME.obj.unwrap_cache by Godot's key
// (bakers/godot/godot_unwrap_key.h). Facts from Godot's editor/import/3d/resource_importer_obj.cpp
// (_parse_obj, ResourceImporterOBJ::import):
// - positions are read as doubles, times the import option scale_mesh plus offset_mesh, stored as
//   float; "vt" v is flipped (1 − v); a face of n corners gives the triangles (i−1, 0, i), i = 2 … n−1,
//   its corners emitted in that order; a corner without a UV or normal keeps the last one set;
// - a surface ends at "usemtl", "o" or the end of the file; each surface's corners are merged by
//   SurfaceTool::index() (equal position, normal, UV, colour and smoothing group: one vertex, numbered
//   in order of first use); the mesh is the surfaces concatenated;
// - with generate_lightmap_uv2 the whole mesh is unwrapped after each surface is added, with an
//   identity transform (a unit scale in the key): the last unwrap, over every surface, is the mesh's.
// Not reproduced: normals Godot generates for a file without "vn" lines (has_normals = false).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace ahd {

struct GodotObjMesh {
  std::vector<float> positions, normals;  // per merged vertex
  std::vector<uint32_t> indices;          // Godot's triangles, surfaces concatenated
  bool has_normals = true;                // the file has "vn" lines
};

// Parses `text` (the .obj file `source`). Pure. Throws ahd::Error("<source>: <cause>") for a face
// index out of range or a malformed line Godot refuses too.
GodotObjMesh parse_godot_obj_mesh(const std::string& text, const std::string& source, const float scale[3],
                                  const float offset[3]);

}  // namespace ahd
