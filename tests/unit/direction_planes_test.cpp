// Model only what a scene needs: a lightmap whose lighting does not depend on the normal is written
// as its I_z plane alone (`--direction auto`), says so in the manifest, the report and the KTX2
// metadata, and decodes to I_z for every normal; directional lighting keeps its planes.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <cmath>
#include <random>
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
#include "fit/hemisphere_error.h"
#include "mips/mips.h"

namespace fs = std::filesystem;
using namespace ahd;
using ahd_test::run_cli;

using namespace ahd_fixture::direction_planes_fixture;


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

// A plain (L0) lightmap's I_z-alone error is taken from its measured fit (the fit is the ambient lobe
// itself): the very figures a measure of the ambient lobes gives, with and without normals, sampled
// and full, negative and uncovered texels included.
TEST(DirectionPlanes, PlainMapAmbientErrorIsItsFitError) {
  ShImage sh = make_sh_image(67, 41, 1);
  std::mt19937 rng(45);
  std::uniform_real_distribution<float> u(-0.2f, 3.0f);
  for (size_t i = 0; i < sh.texels(); ++i) {
    for (int c = 0; c < 3; ++c) sh.texel(i)[c] = i % 13 == 0 ? 0.0f : u(rng);
    sh.coverage[i] = i % 7 != 3;
  }
  ShImage with_normals = sh;
  with_normals.normals.resize(sh.texels() * 3);
  for (size_t i = 0; i < sh.texels(); ++i) {
    const float a = 0.37f * float(i % 17), z = 0.3f + 0.04f * float(i % 11);
    const float r = std::sqrt(1.0f - z * z);
    with_normals.normals[i * 3] = r * std::cos(a), with_normals.normals[i * 3 + 1] = r * std::sin(a), with_normals.normals[i * 3 + 2] = z;
  }
  const Profile p = load_profile("uncompressed");
  const auto same = [](const ErrorStat& a, const ErrorStat& b) { return a.mean == b.mean && a.p99 == b.p99 && a.max == b.max; };
  for (const ShImage* img : {&sh, &with_normals})
    for (Measure m : {Measure::Estimate, Measure::Full}) {
      PipelineOptions opt;
      opt.measure = m;
      opt.measure_baselines = false;
      opt.threads = 1;
      const PipelineResult r = run_conversion(*img, p, opt);
      EXPECT_FALSE(r.directional);
      const FittedLevel level = fit_ambient_level(ShImage(*img), opt.fit, 1);
      const ErrorReport want = m == Measure::Full ? ambient_only_error(level, 1)
                                                  : estimate_error(level.sh, ambient_only_lobes(level), 1);
      const ErrorReport& got = r.ambient_error;
      ASSERT_GT(want.texels, 0u);
      EXPECT_EQ(got.texels, want.texels);
      EXPECT_EQ(got.population, want.population);
      EXPECT_EQ(got.negative, want.negative);
      EXPECT_TRUE(same(got.rmse, want.rmse) && same(got.relative, want.relative) && same(got.log2, want.log2) &&
                  same(got.normal_rel, want.normal_rel))
          << "normals " << !img->normals.empty() << " full " << (m == Measure::Full) << ": relative p99 "
          << got.relative.p99 << " vs " << want.relative.p99;
    }
}
