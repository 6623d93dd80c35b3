// Per-texel normals and coverage of a lightmap, rasterised from a mesh's triangles in its
// lightmap-UV space. World-space SH lightmaps (Godot, Bakery) need each texel's surface normal;
// a baker that does not export a normal map still has the mesh it baked.
//
// UV convention (one rule for every mesh format): row 0 of the lightmap is the top of the image,
// which is v = 1 in the OBJ convention (origin bottom-left, v up) and v = 0 in glTF's (origin
// top-left, v down). MeshTriangles::uv is in the OBJ convention — what Assimp hands over for both
// formats (its glTF importer stores 1 − v itself; io/mesh_io never asks for aiProcess_FlipUVs). So
// texel (x, y) of a W×H lightmap is the square u ∈ [x/W, (x+1)/W], v ∈ [1 − (y+1)/H, 1 − y/H].
//
// Rules (exact, no sampling):
// - Conservative: a texel is covered when some triangle overlaps its square with positive area
//   (touching only along an edge or at a corner is not overlap). Charts drawn with a sample at the
//   texel centre would leave their border texels uncovered, yet bilinear filtering reads them.
// - Per texel the triangle with the largest overlap area wins (each triangle is clipped exactly
//   against the texel square, Sutherland–Hodgman); ties go to the lowest triangle index, so the
//   result does not depend on anything but the input. A texel one triangle covers whole (overlap
//   within 1e-9 of the texel) is that triangle's: later ones skip it, so the cost is each
//   triangle's columns plus the texels it does not close, not N x texels for N large triangles.
// - The normal is the winner's vertex normals interpolated (barycentric) at the centroid of the
//   clipped polygon, then normalised: the point that best represents the part of the texel the
//   triangle owns. Without vertex normals (or when one of the triangle's is zero or non-finite, or
//   the interpolation cancels out) the face normal is used, oriented by the winding
//   (cross(p1 − p0, p2 − p0)).
// - Skipped triangles: zero area in UV space, any non-finite position or UV, or no usable normal
//   (zero-area in 3D and no vertex normals). UVs outside [0, 1] are clipped to the image.
#pragma once
#include <cstdint>
#include <vector>

namespace ahd {

// A triangle soup in plain arrays (one mesh or all meshes of a scene merged).
struct MeshTriangles {
  std::vector<float> positions;  // 3 per vertex (x, y, z), world axes
  std::vector<float> normals;    // 3 per vertex, or empty (face normals are used)
  std::vector<float> uv;         // 2 per vertex: lightmap UV, OBJ convention (v up)
  std::vector<uint32_t> indices; // 3 per triangle
};

struct RasterisedNormals {
  int width = 0, height = 0;
  std::vector<float> normals;      // width*height*3, unit where covered, 0 elsewhere; row 0 = top
  std::vector<uint8_t> coverage;   // width*height, 1 = covered
  std::vector<int32_t> triangle;   // width*height, the winning triangle's index, −1 = none
};

// Rasterises every triangle of `mesh` into a width×height lightmap (rules above). Pure and
// deterministic. Safe on untrusted values (NaN, huge or out-of-range UVs, degenerate triangles);
// throws ahd::Error when the buffers are inconsistent (sizes not multiples of 3/2, normals neither
// empty nor one per vertex, an index out of range) or the size is outside 1..65536.
// Cost: per triangle, the texels of its UV bounding box (clipped to the image).
RasterisedNormals rasterise_lightmap_normals(const MeshTriangles& mesh, int width, int height);

}  // namespace ahd
