// The lossless intermediate: every level's SH and fitted planes survive a write/read exactly,
// and re-quantising from it gives the same planes as the direct conversion.
#include <gtest/gtest.h>

#include <filesystem>

#include "core/error.h"
#include "io/profile_file.h"
#include "io/ahd_intermediate.h"
#include "pipeline/convert.h"
#include "sample/analytic_baker.h"

using namespace ahd;

TEST(Intermediate, RoundTripIsExactAndTranscodeMatchesConvert) {
  BakerOptions bo;
  bo.width = 23;
  bo.height = 17;
  bo.area_samples = 3;
  const ShImage sh = bake_analytic_scene(bo);
  ConvertOptions opt;
  opt.threads = 2;
  ConvertResult direct;
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
    for (size_t i = 0; i < levels[l].ahd.texels.size(); ++i)
      for (int c = 0; c < 3; ++c) {
        ASSERT_EQ(back[l].ahd.texels[i].iz[c], levels[l].ahd.texels[i].iz[c]);
        ASSERT_EQ(back[l].ahd.texels[i].d[c], levels[l].ahd.texels[i].d[c]);
        ASSERT_EQ(back[l].ahd.texels[i].ratio[c], levels[l].ahd.texels[i].ratio[c]);
      }
  }
  ConvertResult again;
  quantise_levels(back, p, opt, &again);
  ASSERT_EQ(again.planes.size(), direct.planes.size());
  for (size_t k = 0; k < direct.planes.size(); ++k)
    for (size_t l = 0; l < direct.planes[k].texture.levels.size(); ++l)
      EXPECT_EQ(again.planes[k].texture.levels[l].data, direct.planes[k].texture.levels[l].data) << direct.planes[k].name;
}

TEST(Intermediate, RefusesOtherFiles) {
  EXPECT_THROW(read_intermediate("/nonexistent/x.ahd.exr", nullptr), Error);
}
