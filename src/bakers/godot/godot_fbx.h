// An .fbx file as Godot's own FBX importer (Godot >= 4.3, ufbx) builds its scene, read through
// Assimp: node names, transforms and each mesh's vertex arrays in the order Godot's importer
// gives them to the lightmap unwrapper, so that the mesh finds its entry of NAME.fbx.unwrap_cache
// by Godot's key (bakers/godot/godot_unwrap_key.h).
//
// Facts from Godot's modules/fbx/fbx_document.cpp (FBXDocument::_parse, _parse_nodes,
// _parse_meshes, _assign_node_names, _gen_unique_name), checked against what Godot 4.6's own
// FBXDocument builds from the files in tests/data/godot/handmade (tests/tools/godot/gen/fbx):
// - ufbx loads with target axes right-handed Y up, target unit 1 m and space conversion
//   MODIFY_GEOMETRY: the geometry and every translation are scaled to metres (the file's
//   UnitScaleFactor is centimetres per unit) but the geometry is not rotated; the axis conversion
//   (the file's CoordAxis/UpAxis/FrontAxis with their signs become +X/+Y/+Z) is applied to the
//   transforms of the file's root nodes only. Geometric transforms are baked into the geometry.
// - the scene's roots are the FBX root node's children; node names are validated as node names
//   ('.', ':', '@', '/', '"', '%' become '_') and made unique over the file by a suffix 2, 3, …
//   ("Skeleton3D" and "RootNode" taken); a nameless node with a mesh is "Mesh", else "Node".
// - a mesh is one surface per material part; each face is triangulated by ufbx (a quad along its
//   shorter diagonal, 0-2 on a tie), each triangle a, b, c taken as c, b, a (Godot's clockwise
//   front faces) and decoded corner by corner, the corners merged into indexed vertices by
//   SurfaceTool::index(): corners equal in every attribute (position, normal, tangent, UV sets,
//   colour) share a vertex, numbered in order of first use.
//
// Not reproduced (the key then differs; the reader falls back to matching triangles, or names the
// instance): ufbx's split of faces with more than 4 corners, normals ufbx generates for a mesh
// without them, the order of material parts when faces use material slots out of order, skinned
// meshes, geometry helper nodes; node names made unique in another order than depth first.
#pragma once
#include <array>
#include <string>
#include <vector>

namespace ahd {

struct GodotFbxMesh {
  std::string name;
  std::vector<float> positions, normals;  // per merged vertex, Godot's space (metres, Y up)
  std::vector<float> uv2;                 // the file's second UV set per vertex (v up), empty when absent
  std::vector<uint32_t> indices;          // Godot's triangles (clockwise front faces), surfaces concatenated
  bool has_normals = true;                // every corner had a normal in the file
  bool polygons = false;                  // faces of more than 4 corners were split (a fan, not ufbx's split)
};

struct GodotFbxNode {
  std::string name;               // as Godot names it
  int parent = -1;                // −1: a root of the file (a child of the imported scene's root)
  std::array<float, 16> local{};  // Godot's space, row-major 4×4 (rows of the basis, origin in column 3)
  int mesh = -1;                  // into GodotFbxScene::meshes
};

struct GodotFbxScene {
  std::vector<GodotFbxNode> nodes;  // parents before children
  std::vector<GodotFbxMesh> meshes;
  double unit_scale = 1;  // metres per file unit
  bool mirrored = false;  // the file's axes are left-handed (the conversion mirrors)
};

// Reads `path` (binary or ASCII FBX). Throws ahd::Error("<path>: <cause>") when Assimp cannot read it.
GodotFbxScene read_godot_fbx(const std::string& path);

}  // namespace ahd
