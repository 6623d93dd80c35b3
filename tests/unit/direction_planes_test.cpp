// Model only what a scene needs: a lightmap whose lighting does not depend on the normal is written
// as its I_z plane alone (`--direction auto`), says so in the manifest, the report and the KTX2
// metadata, and decodes to I_z for every normal; directional lighting keeps its planes.
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

namespace fs = std::filesystem;
using namespace ahd;
using ahd_test::run_cli;

namespace {

nlohmann::json read_json(const fs::path& p) {
  std::ifstream f(p);
  return nlohmann::json::parse(f);
}

std::vector<std::string> plane_names(const nlohmann::json& manifest) {
  std::vector<std::string> names;
  for (const auto& p : manifest.at("planes")) names.push_back(p.at("name").get<std::string>());
  return names;
}

// A plain lightmap (E/π along the normal) as the `plain` layout reads it.
fs::path write_plain(const fs::path& dir) {
  ImageF img(8, 6, 3);
  for (size_t i = 0; i < img.data.size(); ++i) img.data[i] = 0.2f + 0.05f * float(i % 7);
  write_image((dir / "flat.exr").string(), img);
  return dir / "flat";
}

}  // namespace

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

TEST(DirectionPlanes, AutoKeepsDirectionalLightAndDropsWeakOne) {
  BakerOptions bo;
  bo.width = bo.height = 32;
  const ShImage scene = bake_analytic_scene(bo);
  const Profile p = load_profile("uncompressed");
  PipelineOptions opt;
  opt.measure = Measure::Full;
  opt.measure_baselines = false;
  PipelineResult strong = run_conversion(scene, p, opt);
  EXPECT_TRUE(strong.directional) << strong.direction_reason;
  EXPECT_EQ(strong.planes.size(), 3u);
  EXPECT_GT(strong.ambient_error.relative.p99, 0.1);  // the sample's light is strongly directional

  ShImage weak = scene;  // the same light with its directional part 1000× weaker
  for (size_t i = 0; i < weak.texels(); ++i)
    for (int k = 3; k < weak.coeffs * 3; ++k) weak.texel(i)[k] *= 1e-3f;
  const PipelineResult w = run_conversion(weak, p, opt);
  EXPECT_FALSE(w.directional) << w.direction_reason;
  ASSERT_EQ(w.planes.size(), 1u);
  EXPECT_EQ(w.planes[0].name, "iz");
  EXPECT_LE(w.ambient_error.relative.p99, kDefaultAmbientThreshold);
  // What was dropped costs no more than the threshold: the final error is the I_z-alone error.
  EXPECT_NEAR(w.final_error.relative.p99, w.ambient_error.relative.p99, 1e-3);
}

TEST(DirectionPlanes, ManifestChecksItsPlanes) {
  Manifest m;
  m.profile = "uncompressed";
  m.container = "ktx2";
  m.width = m.height = 4;
  m.planes.push_back({"iz", "a.iz.ktx2", PixelFormat::RGBA16_SFLOAT, 4, 4, 1, 10, std::string(64, 'a')});
  // Directional but without direction planes: refused, saying why.
  try {
    manifest_from_json(manifest_to_json(m), "m.json");
    ADD_FAILURE() << "a directional manifest without dir/ratio planes was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("lacks its direction/ratio planes"), std::string::npos) << e.what();
  }
  m.directional = false;
  const Manifest back = manifest_from_json(manifest_to_json(m), "m.json");
  EXPECT_FALSE(back.directional);
  ASSERT_EQ(back.planes.size(), 1u);
  m.planes.clear();  // and no manifest without its iz plane
  EXPECT_THROW(manifest_from_json(manifest_to_json(m), "m.json"), Error);
}

TEST(DirectionPlanes, EarlyExitDecisionEqualsTheMeasuredP99) {
  // relative_p99_exceeds must answer exactly what measure_error's p99 says, for thresholds on
  // both sides of it and at it, on a strong and a weak directional scene.
  BakerOptions bo;
  bo.width = bo.height = 24;
  ShImage scene = bake_analytic_scene(bo);
  for (float scale : {1.0f, 0.003f}) {
    ShImage sh = scene;
    for (size_t i = 0; i < sh.texels(); ++i)
      for (int k = 3; k < sh.coeffs * 3; ++k) sh.texel(i)[k] *= scale;
    PipelineOptions opt;
    opt.measure = Measure::Off;
    PipelineResult r;
    const std::vector<FittedLevel> levels = fit_levels(sh, opt, &r);
    const std::vector<AhdLobe> lobes = ambient_only_lobes(levels[0]);
    const double p99 = measure_error(levels[0].sh, lobes, 1).relative.p99;
    ASSERT_GT(p99, 0.0);
    for (double t : {p99 * 0.5, p99 * 0.999, p99, p99 * 1.001, p99 * 2})
      EXPECT_EQ(relative_p99_exceeds(levels[0].sh, lobes, t), p99 > t) << "scale " << scale << " threshold " << t;
  }
}
