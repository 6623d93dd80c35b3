// Shared by the Godot scene tests: a real Godot bake read as convert reads it, with the normals
// rasterised from its scene turned on purpose (normals that are not the bake's own).
#pragma once
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <utility>
#include <vector>

#include "bakers/baker_layout.h"
#include "bakers/godot/godot_scene.h"
#include "scene/lightmap_raster.h"
#include "scene/placement.h"

namespace ahd_test {

struct TurnedBake {
  ahd::ShImage sh;
  std::vector<uint8_t> coverage;  // the rasterised coverage, 512 x 512
};

// `scenes`/world.tscn (a godot4-unpacked bake beside it, `scenes`/world*) read with the scene's
// normals rasterised at 512 x 512, each covered texel's normal turned about x by `degrees`.
inline TurnedBake read_turned_bake(const std::filesystem::path& scenes, double degrees) {
  using namespace ahd;
  const GodotSceneMeshes g = load_godot_scene((scenes / "world.tscn").string());
  const PlacedMesh pm = place_instances(g.scene, g.placements, 0, g.lmbake);
  RasterisedNormals rn = rasterise_lightmap_normals(pm.mesh, 512, 512);
  const double c = std::cos(degrees * M_PI / 180), s = std::sin(degrees * M_PI / 180);
  for (size_t i = 0; i < rn.coverage.size(); ++i) {
    float* n = &rn.normals[i * 3];
    if (!rn.coverage[i]) continue;
    const double y = n[1], z = n[2];
    n[1] = float(c * y - s * z), n[2] = float(s * y + c * z);
  }
  TurnedBake out{{}, rn.coverage};
  const LayoutNormals ln{"world.tscn", 512, 512, std::move(rn.normals), std::move(rn.coverage)};
  out.sh = read_layout(load_layout("godot4-unpacked"), (scenes / "world").string(), &ln);
  return out;
}

}  // namespace ahd_test
