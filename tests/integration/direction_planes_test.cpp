// --direction auto/keep/drop through the command. In-process tests: tests/unit/direction_planes_test.cpp.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_runner.h"
#include "files/container_file.h"
#include "core/error.h"
#include "files/profile_file.h"
#include "image/image_io.h"
#include "pipeline/convert.h"
#include "pipeline/manifest.h"
#include "sample/analytic_baker.h"
#include "direction_planes_fixture.h"

namespace fs = std::filesystem;
using namespace ahd;
using ahd_test::run_cli;

using namespace ahd_fixture::direction_planes_fixture;

TEST(DirectionPlanes, PlainLightmapWritesOnlyIz) {
  const fs::path d = ahd_test::temp_dir("dir_plain");
  const fs::path base = write_plain(d);
  const auto r = run_cli({"convert", base.string(), "--layout", "plain", "-o", (d / "out.ktx2").string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("direction and ratio planes dropped"), std::string::npos) << r.output;
  const auto m = read_json(d / "out.json");
  EXPECT_EQ(plane_names(m), std::vector<std::string>{"iz"});
  EXPECT_FALSE(m.at("directional").get<bool>());
  EXPECT_EQ(ahd_test::plane_file((d / "out.json").string(), "dir"), "");
  EXPECT_EQ(ahd_test::plane_file((d / "out.json").string(), "ratio"), "");
  size_t files = 0;
  for (const auto& e : fs::directory_iterator(d)) files += e.path().filename().string().rfind("out.", 0) == 0;
  EXPECT_EQ(files, 3u);  // iz, manifest, report
  const auto rep = read_json(d / "out.report.json");
  EXPECT_EQ(rep.at("direction").at("planes"), "dropped");
  EXPECT_LT(rep.at("direction").at("iz_only_error").at("relative").at("p99").get<double>(), 1e-6);
  // The plane says it too (KTX2 key/value data).
  const Texture t = read_container_file(ahd_test::plane_file((d / "out.json").string(), "iz"));
  bool found = false;
  for (const auto& [k, v] : t.metadata) found |= k == "ahd.directional" && v == "0";
  EXPECT_TRUE(found);

  // Decoded for a tilted normal, the plane is still I_z, stored at the input's own scale (E/π,
  // iz_scale 1/π: issue 42, a plain map dropped back into an engine is as bright as before).
  ImageF normals(8, 6, 3);
  for (size_t i = 0; i < normals.texels(); ++i) normals.data[i * 3] = 0.6f, normals.data[i * 3 + 2] = 0.8f;
  write_image((d / "n.exr").string(), normals);
  const auto dec = run_cli({"decode", (d / "out.json").string(), "-o", (d / "e.exr").string(), "--normals",
                            (d / "n.exr").string()});
  ASSERT_EQ(dec.exit_code, 0) << dec.output;
  const ImageF e = read_image((d / "e.exr").string());
  for (size_t i = 0; i < e.texels(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double want = 0.2 + 0.05 * double((i * 3 + c) % 7);
      EXPECT_NEAR(e.data[i * 3 + c], want, want * 2e-3) << i;  // RGBA16F I_z: half precision
    }
}

TEST(DirectionPlanes, KeepAndDropOverrideTheMeasure) {
  const fs::path d = ahd_test::temp_dir("dir_override");
  const fs::path base = write_plain(d);
  auto r = run_cli({"convert", base.string(), "--layout", "plain", "--direction", "keep", "-o", (d / "k.ktx2").string(), "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(plane_names(read_json(d / "k.json")), (std::vector<std::string>{"iz", "dir", "ratio"}));
  r = run_cli({"convert", "--sample-size", "32", "--direction", "drop", "--profile", "pc-bc", "-o", (d / "s.dds").string(), "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(plane_names(read_json(d / "s.json")), std::vector<std::string>{"iz"});
  r = run_cli({"convert", "--sample-size", "32", "--direction", "sideways", "-o", (d / "x.ktx2").string()});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_FALSE(fs::exists(d / "x.json"));
}
