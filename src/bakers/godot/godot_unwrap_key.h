// Godot's key of a lightmap unwrap-cache entry (NAME.glb.unwrap_cache, bakers/godot/godot_unwrap_cache.h),
// computed without Godot so that each mesh finds its own entry — not another mesh's of the same
// vertex count.
//
// Facts from Godot's modules/xatlas_unwrap/register_types.cpp (the key: an MD5 over the texel size
// as a float, the indices as int32, the positions and then the normals as float triples, all as
// handed to the unwrapper) and scene/resources/importer_mesh.cpp (ImporterMesh::
// lightmap_unwrap_cached: what is handed over — the mesh's surfaces concatenated, positions
// multiplied by the scale of the node's transform in the imported scene (the lengths of the basis
// columns; rotation and translation dropped) plus a zero origin, normals by the inverse transpose of
// that scale and renormalised, triangles with an edge shorter than sqrt(1.19209290e-7) dropped).
// The texel size is the import option meshes/lightmap_texel_size
// (editor/import/3d/resource_importer_scene.cpp). Godot computes in float; so does this.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ahd {

using GodotUnwrapKey = std::array<uint8_t, 16>;

// RFC 1321 MD5 of `size` bytes. Pure.
GodotUnwrapKey md5_digest(const void* data, size_t size);

// Godot's key for a mesh whose surfaces are concatenated in `positions`/`normals` (3 floats per
// vertex, as the file stores them) with triangles `indices` in Godot's winding (clockwise front
// faces: a glTF triangle a, b, c is Godot's a, c, b), unwrapped at `texel_size` under a node
// whose scale is `scale` (godot_node_scale). Pure; indices must be < the vertex count.
GodotUnwrapKey godot_unwrap_key(const std::vector<float>& positions, const std::vector<float>& normals,
                                const std::vector<uint32_t>& indices, const float scale[3], float texel_size);

// The scale Godot keeps of a node's accumulated basis `rows` (3×3, row-major): each column's length
// in float, as Basis::get_column(i).length() computes it.
void godot_node_scale(const float rows[9], float scale[3]);

// The basis Godot builds for a glTF node's rotation (quaternion x, y, z, w) and scale
// (Basis::set_quaternion_scale: the rotation times the diagonal scale), in float. Row-major.
void godot_basis_from_trs(const float quat[4], const float scale[3], float rows[9]);

// a · b in float, as Godot's Basis::operator* rounds it. Row-major.
void godot_basis_mul(const float a[9], const float b[9], float out[9]);

// "0123…" (32 lowercase hex digits), the form Godot sorts the cache's entries by.
std::string godot_unwrap_key_hex(const GodotUnwrapKey& key);

}  // namespace ahd
