// Atlas placement of mesh instances: real bakers pack many instances into one atlas, each by a
// scale and offset of its own lightmap UVs (Unity: m_LightmapIndex + m_LightmapTilingOffset per
// renderer; Godot: a rectangle and a slice per user). Before rasterising, each instance's UVs are
// moved into its rectangle: atlas_uv = uv · scale + offset, in the v-up (OBJ / Unity) convention
// of MeshTriangles::uv.
#pragma once
#include <string>
#include <vector>

#include "scene/mesh_io.h"

namespace ahd {

struct Placement {
  std::string node;  // the instance's node name
  int page = 0;      // atlas page (array layer)
  double scale[2] = {1, 1}, offset[2] = {0, 0};
};

struct PlacedMesh {
  MeshTriangles mesh;                 // the page's instances, UVs in atlas space
  std::vector<std::string> placed;    // the instances on this page, in scene order
  std::vector<std::string> unplaced;  // instances no placement names (left out of every page)
  std::vector<std::string> overlaps;  // "A and B" for the first kMaxListedOverlaps overlapping pairs on this page
  size_t overlap_count = 0;           // every overlapping pair, counted (pairs grow as instances²: not listed)
};

// The overlapping pairs place_instances names (the rest are counted).
constexpr size_t kMaxListedOverlaps = 20;

// The instances of `scene` that `placements` put on `page`, their UVs transformed. Throws
// ahd::Error when a placement has a non-finite or non-positive scale, or names a node the scene
// lacks (`source` names the placement in the message). Overlap: the UV bounding rectangles of two
// placed instances intersect with positive area (shared edges are not overlap).
PlacedMesh place_instances(const MeshInstances& scene, const std::vector<Placement>& placements, int page,
                           const std::string& source);

// Every instance of `scene` at scale 1, offset 0 on `page`: the UVs as stored (to find overlaps
// of instances given without placement).
std::vector<Placement> identity_placements(const MeshInstances& scene, int page = 0);

}  // namespace ahd
