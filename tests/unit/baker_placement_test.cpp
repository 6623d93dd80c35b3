// Atlas placement for normals (issue 16): three instances of one mesh placed in one atlas by
// scale/offset (ahdpack's JSON, a Unity-style scene YAML) rasterise to the same normals and
// coverage as the same scene whose lightmap UVs were baked into atlas space; overlaps reported.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "fixture_writers.h"
#include "files/file_io.h"
#include "scene/mesh_io.h"
#include "scene/placement_io.h"
#include "layout_test_scene.h"
#include "scene/placement.h"
#include "baker_placement_fixture.h"

namespace fs = std::filesystem;
using namespace ahd;
using namespace layout_test;
using namespace ahd_fixture::baker_placement_fixture;

TEST(Placement, InstancesPlacedByJsonAndUnityYamlEqualUvsBakedIntoTheAtlas) {
  const fs::path d = ahd_test::temp_dir("placement");
  write_placement_inputs(d);

  const RasterisedNormals want = rasterise_lightmap_normals(read_mesh_lightmap((d / "baked.gltf").string(), -1), kAtlas, kAtlas);
  size_t covered = 0;
  for (uint8_t c : want.coverage) covered += c;
  EXPECT_GT(covered, 300u);
  // The three normals are where the rectangles put them (row 0 = top = v 1: Chair top left).
  const float* chair = &want.normals[(4 * kAtlas + 4) * 3];
  const float* table = &want.normals[(4 * kAtlas + 20) * 3];
  const float* lamp = &want.normals[(28 * kAtlas + 12) * 3];
  EXPECT_NEAR(chair[1], 0.6, 1e-6);
  EXPECT_NEAR(chair[2], 0.8, 1e-6);
  EXPECT_NEAR(table[1], -0.6, 1e-6);
  EXPECT_NEAR(table[2], -0.8, 1e-6);
  EXPECT_NEAR(lamp[1], 0.6, 1e-6);
  EXPECT_NEAR(lamp[2], -0.8, 1e-6);

  const MeshInstances scene = read_mesh_instances((d / "instanced.gltf").string(), -1);
  ASSERT_EQ(scene.instances.size(), 3u);
  for (const char* file : {"p.json", "scene.unity"}) {
    const std::vector<Placement> pl = read_placements((d / file).string());
    ASSERT_EQ(pl.size(), 3u) << file;
    const PlacedMesh pm = place_instances(scene, pl, 0, file);
    EXPECT_EQ(pm.placed.size(), 3u);
    EXPECT_TRUE(pm.overlaps.empty()) << file;
    expect_same_raster(rasterise_lightmap_normals(pm.mesh, kAtlas, kAtlas), want, file);
    EXPECT_TRUE(place_instances(scene, pl, 1, file).mesh.indices.empty());  // nothing on page 1
  }
  // Without placement the three instances pile up in the same rectangle: a different raster.
  const RasterisedNormals piled = rasterise_lightmap_normals(scene.mesh, kAtlas, kAtlas);
  EXPECT_NE(piled.coverage, want.coverage);

  // Overlapping rectangles are reported; unknown nodes and bad scales refused.
  const double overlapping[3][4] = {{0.5, 0.5, 0, 0.5}, {0.5, 0.5, 0.25, 0.5}, {0.5, 0.25, 0.25, 0}};
  write_json((d / "over.json").string(), overlapping);
  const PlacedMesh over = place_instances(scene, read_placements((d / "over.json").string()), 0, "over.json");
  ASSERT_EQ(over.overlaps.size(), 1u);
  EXPECT_EQ(over.overlaps[0], "'Chair' and 'Table'");
  std::vector<Placement> bad = read_placements((d / "p.json").string());
  bad[0].node = "Sofa";
  expect_error([&] { place_instances(scene, bad, 0, "p.json"); }, "'Sofa', which is no mesh instance");
  bad = read_placements((d / "p.json").string());
  bad[1].scale[0] = 0;
  expect_error([&] { place_instances(scene, bad, 0, "p.json"); }, "finite positive scale");
  std::ofstream(d / "broken.json") << "{\"placements\": [{\"node\": 3}]}";
  expect_error([&] { read_placements((d / "broken.json").string()); }, "malformed placement JSON");
  fs::remove_all(d);
}
