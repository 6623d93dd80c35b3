// End to end in memory: the analytic scene through fit, quantisation and the reference decoder.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "files/profile_file.h"
#include "fit/ahd_decode.h"
#include "fit/fit_image.h"
#include "pipeline/convert.h"
#include "pipeline/plane_codec.h"
#include "sample/analytic_baker.h"

using namespace ahd;

namespace {

ShImage pipeline_scene(int size, int coeffs, uint32_t seed = 0) {
  BakerOptions bo;
  bo.width = bo.height = size;
  bo.coeffs = coeffs;
  bo.seed = seed;
  bo.area_samples = 4;
  return bake_analytic_scene(bo);
}

}  // namespace

TEST(Pipeline, AnalyticSceneFitKeepsIzAndSigns) {
  for (int coeffs : {4, 9}) {
    const ShImage sh = pipeline_scene(64, coeffs);
    FitOptions opt;
    FitStats st;
    const AhdImage fit = fit_image(sh, opt, 2, &st);
    EXPECT_GT(st.covered, 3000u);
    for (size_t i = 0; i < sh.texels(); ++i) {
      if (!sh.coverage[i]) continue;
      IrradiancePoly p[3];
      local_polys(sh, i, p);
      const AhdFit f = fit.texel(i);
      for (int c = 0; c < 3; ++c) {
        const double ez = p[c].e0 + p[c].e[2] + p[c].q[2][2];
        ASSERT_GT(ez, 0.0);
        ASSERT_NEAR(f.iz[c], ez, 1e-5 * ez);
        ASSERT_NEAR(double(fitted_ca(f, c)) + double(f.d[2]) * fitted_cd(f, c), ez, 1e-5 * ez);
        ASSERT_GE(fitted_ca(f, c), 0.0f);
        ASSERT_GE(fitted_cd(f, c), 0.0f);
      }
    }
  }
}

TEST(Pipeline, BakerIsDeterministicAndThreadIndependent) {
  BakerOptions a;
  a.width = a.height = 48;
  a.threads = 1;
  BakerOptions b = a;
  b.threads = 2;
  const ShImage x = bake_analytic_scene(a), y = bake_analytic_scene(b);
  EXPECT_EQ(x.data, y.data);
  EXPECT_EQ(x.coverage, y.coverage);
  a.seed = 7;
  EXPECT_NE(bake_analytic_scene(a).data, x.data);
}

TEST(Pipeline, BakerHandlesTinyAndOddSizes) {
  for (auto [w, h] : {std::pair{1, 1}, {4, 4}, {3, 5}, {17, 9}}) {
    BakerOptions o;
    o.width = w;
    o.height = h;
    const ShImage s = bake_analytic_scene(o);
    ASSERT_EQ(s.texels(), size_t(w) * h);
    for (float v : s.data) ASSERT_TRUE(std::isfinite(v));
  }
}

TEST(Pipeline, UncompressedProfileClosedLoopBeatsOpenLoop) {
  const ShImage sh = pipeline_scene(64, 9);
  PipelineOptions opt;
  opt.measure = Measure::Full;
  opt.threads = 2;
  const PipelineResult r = run_conversion(sh, load_profile("uncompressed"), opt);
  ASSERT_EQ(r.planes.size(), 3u);
  EXPECT_EQ(r.planes[0].texture.format, PixelFormat::RGBA16_SFLOAT);
  EXPECT_EQ(r.planes[1].texture.format, PixelFormat::RG8_UNORM);
  EXPECT_EQ(r.planes[2].texture.format, PixelFormat::R8_UNORM);
  EXPECT_EQ(r.fit_error.negative, 0u);
  EXPECT_GT(r.unconstrained_error.normal_rel.max, r.fit_error.normal_rel.max)
      << "the unconstrained fit does not keep I_z; ours does";
  EXPECT_LT(r.fit_error.normal_rel.max, 1e-5);
  // I_z survives half-float quantisation within half precision.
  EXPECT_LT(r.final_error.normal_rel.max, 2e-3);
  EXPECT_LE(r.final_error.relative.mean, r.open_loop_error.relative.mean * 1.0001);
  EXPECT_LT(r.final_error.relative.mean, 0.25);
}

TEST(Pipeline, ConvertIsDeterministicAcrossThreadCounts) {
  const ShImage sh = pipeline_scene(40, 9);
  PipelineOptions a;
  a.threads = 1;
  PipelineOptions b = a;
  b.threads = 2;
  const PipelineResult x = run_conversion(sh, load_profile("uncompressed"), a);
  const PipelineResult y = run_conversion(sh, load_profile("uncompressed"), b);
  ASSERT_EQ(x.planes.size(), y.planes.size());
  for (size_t p = 0; p < x.planes.size(); ++p) EXPECT_EQ(x.planes[p].texture.levels[0].data, y.planes[p].texture.levels[0].data);
}

TEST(Pipeline, DecodedPlanesReproduceIzAtTexelCentres) {
  const ShImage sh = pipeline_scene(32, 9);
  PipelineOptions opt;
  const PipelineResult r = run_conversion(sh, load_profile("uncompressed"), opt);
  const DecodedPlanes p = decode_planes(r.planes, false);
  for (size_t i = 0; i < sh.texels(); ++i) {
    const double z[3] = {0, 0, 1};
    double e[3];
    decode_irradiance(&p.iz[i * 3], &p.d[i * 3], &p.ratio[i * 3], z, opt.fit.dz_min, e);
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(e[c], p.iz[i * 3 + c], 1e-6 * p.iz[i * 3 + c] + 1e-30);
  }
}

// The error estimate decodes one texel at a time (decode_plane_texel: the block alone, on the
// stack); every texel must read as whole-level decoding reads it, bit for bit, in every format a
// profile can write, on random bytes and an odd size (partial blocks at the right and bottom).
TEST(Pipeline, OneTexelDecodeIsWholeLevelDecode) {
  std::mt19937 rng(11);
  for (const PixelFormatRow& row : pixel_format_rows()) {
    if (!row.decode) continue;  // a format this build cannot decode
    const PixelFormat f = row.info.format;
    TextureLevel lvl;
    lvl.width = 9;
    lvl.height = 7;
    lvl.data.resize(level_size_bytes(f, lvl.width, lvl.height));
    for (uint8_t& b : lvl.data) b = uint8_t(rng());
    const ImageF all = decode_plane(f, lvl);
    for (uint32_t y = 0; y < lvl.height; ++y)
      for (uint32_t x = 0; x < lvl.width; ++x) {
        float v[4] = {};
        decode_plane_texel(f, lvl, x, y, v);
        ASSERT_EQ(std::memcmp(v, all.at(int(x), int(y)), sizeof(float) * size_t(all.channels)), 0)
            << format_info(f).name << " texel " << x << "," << y;
      }
  }
}
