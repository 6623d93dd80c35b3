// Godot 4 primitive meshes (BoxMesh, PlaneMesh, QuadMesh, PrismMesh, CylinderMesh, CapsuleMesh,
// SphereMesh, TorusMesh) rebuilt from the properties a .tscn writes for them, with the lightmap UVs
// (UV2) Godot generates when `add_uv2 = true`. A scene lit by LightmapGI bakes these meshes through
// their UV2, so a lightmap's texels map back to the surface only through the same formulas.
//
// The facts (vertex order, UV2 chart layout, padding, lightmap_size_hint, property defaults and the
// setters' clamps) come from Godot 4.6's scene/resources/3d/primitive_meshes.cpp and .h; the
// arithmetic is done in the same float/double mix as there, so the result matches Godot's arrays to
// float rounding (tests/unit/godot_primitives_test.cpp compares with arrays Godot 4.6 wrote).
#pragma once
#include <array>
#include <map>
#include <string>

#include "scene/lightmap_raster.h"

namespace ahd {

// The primitive mesh resource types whose geometry this file reproduces: BoxMesh, PlaneMesh,
// QuadMesh, PrismMesh, CylinderMesh, CapsuleMesh, SphereMesh, TorusMesh. (TubeTrailMesh,
// RibbonTrailMesh, PointMesh and TextMesh are not: particles and text are not lightmapped.)
bool is_godot_primitive_mesh(const std::string& type);

// `props`: the sub_resource's properties as written in the .tscn (name -> raw value text, e.g.
// "Vector3(4, 0.2, 4)", "true", "2.0", "1"); missing ones take Godot 4.6's defaults; properties
// that change neither geometry nor UV2 (material, custom_aabb, lightmap_size_hint, ...) are ignored.
// They are applied the way loading the .tscn applies them: in Godot's property order (the
// PrimitiveMesh ones, then the type's), through the setters' rules — e.g. a CapsuleMesh radius
// above height/2 raises the height, a later height lowers the radius again; radial_segments below
// 4 become 4; a negative subdivide becomes 0; an out-of-range rings is ignored (Godot keeps the
// previous value and prints an error).
// `texel_size`: the project setting rendering/lightmapping/primitive_meshes/texel_size (Godot's
// default 0.2; <= 0 means 0.2 as in Godot); uv2_padding is in texels of that size.
//
// Returns the mesh in its local space with Godot's positions, normals (flip_faces applied) and
// UV2 in `uv` with v flipped to v-up (uv.v = 1 - Godot's v), indices as Godot's (front faces
// clockwise, Godot's rule: cross(p1 - p0, p2 - p0) points against the normal). One surface.
//
// Safe on untrusted input. Throws ahd::Error("<source>: <cause>") when: the type is not one of the
// above; `add_uv2` is not true (Godot gives the primitive no lightmap UVs); a value used is
// malformed (not a number, bool or Vector2/3 literal, or not finite; integers must be integers
// within +-1e6); PlaneMesh orientation is not 0, 1 or 2; TorusMesh inner_radius == outer_radius
// (Godot builds no mesh); the mesh would have more than 2^22 vertices (4 194 304: bound on the
// subdivisions, rings and segments); a position, normal or UV2 comes out non-finite (a degenerate
// size such as a zero radius). Pure, thread-safe.
//
// Normals are those Godot's RenderingServer hands back (and LightmapGI bakes with): stored as
// 16-bit octahedral pairs, so within ~3e-5 of the exact unit vector. Matches Godot 4.6's arrays
// (tests/data/godot/generated/primitives.json) bit for bit in positions, normals and UV2 u, and
// within 4e-8 in UV2 v (1 - v rounds once more).
MeshTriangles godot_primitive_mesh(const std::string& type, const std::map<std::string, std::string>& props,
                                   const std::string& source, float texel_size = 0.2f);

// Godot's Mesh.lightmap_size_hint of the same primitive (width, height in texels), as
// PrimitiveMesh::_update_lightmap_size leaves it after the .tscn is loaded: LightmapGI sizes the
// mesh's lightmap chart from it. Note TorusMesh's radius setters do not refresh it in Godot 4.6, so
// its hint is that of the default radii (0.5, 1.0). Same inputs, contract and errors as above.
std::array<int, 2> godot_primitive_lightmap_size_hint(const std::string& type,
                                                      const std::map<std::string, std::string>& props,
                                                      const std::string& source, float texel_size = 0.2f);

}  // namespace ahd
