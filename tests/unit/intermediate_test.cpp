// The lossless intermediate: every level's SH and fitted planes survive a write/read exactly,
// and re-quantising from it gives the same planes as the direct conversion.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "core/error.h"
#include "files/profile_file.h"
#include "image/ahd_intermediate.h"
#include "pipeline/convert.h"
#include "sample/analytic_baker.h"

using namespace ahd;

static ShImage small_scene(int width, int height, int area_samples) {
  BakerOptions bo;
  bo.width = width;
  bo.height = height;
  bo.area_samples = area_samples;
  return bake_analytic_scene(bo);
}

TEST(Intermediate, RoundTripIsExactAndTranscodeMatchesConvert) {
  const ShImage sh = small_scene(23, 17, 3);
  PipelineOptions opt;
  opt.threads = 2;
  PipelineResult direct;
  const std::vector<FittedLevel> levels = fit_levels(sh, opt, &direct);
  const Profile p = load_profile("uncompressed");
  quantise_levels(levels, p, opt, &direct);

  const std::string path = (std::filesystem::temp_directory_path() / "ahd_intermediate_test.ahd.exr").string();
  write_intermediate(path, levels, opt.fit);
  FitOptions fit;
  fit.dz_min = 0.5;  // must be overwritten by the file's value
  const std::vector<FittedLevel> back = read_intermediate(path, &fit);
  std::filesystem::remove(path);
  EXPECT_EQ(fit.dz_min, opt.fit.dz_min);
  ASSERT_EQ(back.size(), levels.size());
  for (size_t l = 0; l < levels.size(); ++l) {
    EXPECT_EQ(back[l].sh.data, levels[l].sh.data);
    EXPECT_EQ(back[l].sh.coverage, levels[l].sh.coverage);
    for (size_t i = 0; i < levels[l].ahd.size(); ++i)
      for (int c = 0; c < 3; ++c) {
        ASSERT_EQ(back[l].ahd.texel(i).iz[c], levels[l].ahd.texel(i).iz[c]);
        ASSERT_EQ(back[l].ahd.texel(i).d[c], levels[l].ahd.texel(i).d[c]);
        ASSERT_EQ(back[l].ahd.texel(i).ratio[c], levels[l].ahd.texel(i).ratio[c]);
      }
  }
  PipelineResult again;
  quantise_levels(back, p, opt, &again);
  ASSERT_EQ(again.planes.size(), direct.planes.size());
  for (size_t k = 0; k < direct.planes.size(); ++k)
    for (size_t l = 0; l < direct.planes[k].texture.levels.size(); ++l)
      EXPECT_EQ(again.planes[k].texture.levels[l].data, direct.planes[k].texture.levels[l].data) << direct.planes[k].name;
}

TEST(Intermediate, RefusesOtherFiles) {
  EXPECT_THROW(read_intermediate("/nonexistent/x.ahd.exr", nullptr), Error);
}

// convert() stores no fit for L0 images (plain lightmaps: ambient-only levels); the stored chain
// (fit_levels, what --keep-intermediate writes) fits them in full. Both must write the same bytes.
TEST(Intermediate, PlainL0ConversionWritesTheStoredChainsBytes) {
  const ShImage l2 = small_scene(29, 19, 2);
  ShImage sh = make_sh_image(l2.width, l2.height, 1);
  for (size_t i = 0; i < sh.texels(); ++i)
    for (int c = 0; c < 3; ++c) sh.texel(i)[c] = l2.texel(i)[c];
  sh.coverage = l2.coverage;
  ASSERT_GT(std::count(sh.coverage.begin(), sh.coverage.end(), 0), 0);  // dilated texels are in the blocks
  for (const char* profile : {"pc-bc", "uncompressed"}) {
    for (DirectionPlanes dir : {DirectionPlanes::Auto, DirectionPlanes::Keep}) {
      PipelineOptions opt;
      opt.threads = 2;
      opt.direction = dir;
      const Profile p = load_profile(profile);
      PipelineResult stored;
      quantise_levels(fit_levels(sh, opt, &stored), p, opt, &stored);
      const PipelineResult streamed = run_conversion(sh, p, opt);
      ASSERT_EQ(streamed.planes.size(), stored.planes.size()) << profile;
      for (size_t k = 0; k < stored.planes.size(); ++k)
        for (size_t l = 0; l < stored.planes[k].texture.levels.size(); ++l)
          EXPECT_EQ(streamed.planes[k].texture.levels[l].data, stored.planes[k].texture.levels[l].data)
              << profile << " " << stored.planes[k].name << " level " << l;
      EXPECT_EQ(streamed.fit_stats.covered, stored.fit_stats.covered);
      EXPECT_EQ(streamed.fit_stats.no_direction, stored.fit_stats.no_direction);
    }
  }
}
