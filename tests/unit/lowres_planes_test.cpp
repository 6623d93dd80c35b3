// Direction and ratio planes below the lightmap's resolution (issue 43, "dir_ratio_scale"): I_z
// keeps its exact full-resolution bytes, the side planes are ceil(W/s) × ceil(H/s) with their own
// chain, the decoder samples them bilinearly at the full-res texel centres (clamp to edge), and
// every decoded texel keeps the constraints.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "fit/ahd_decode.h"
#include "fit/lowres_fit.h"
#include "pipeline/convert.h"
#include "pipeline/manifest.h"
#include "pipeline/plane_decode.h"
#include "pipeline/plane_scale.h"
#include "pipeline/profile.h"
#include "sample/analytic_baker.h"

using namespace ahd;

namespace {

const Plane& plane_named(const PipelineResult& r, const std::string& name) {
  for (const Plane& p : r.planes)
    if (p.name == name) return p;
  throw Error("no plane " + name);
}

ShImage scene(int w, int h) {
  BakerOptions bo;
  bo.width = w, bo.height = h;
  return bake_analytic_scene(bo);
}

}  // namespace

TEST(LowResPlanes, BilinearTapsAreTheGpusAtTexelCentres) {
  // A 4-texel row sampled from a 2-texel row: centres at t = −0.25, 0.25, 0.75, 1.25 (clamped).
  const BilinearTap t0 = bilinear_tap(4, 2, 0), t1 = bilinear_tap(4, 2, 1), t2 = bilinear_tap(4, 2, 2),
                    t3 = bilinear_tap(4, 2, 3);
  EXPECT_EQ(t0.x0, 0);
  EXPECT_EQ(t0.x1, 0);
  EXPECT_EQ(t1.x0, 0);
  EXPECT_EQ(t1.x1, 1);
  EXPECT_DOUBLE_EQ(t1.w1, 0.25);
  EXPECT_EQ(t2.x0, 0);
  EXPECT_EQ(t2.x1, 1);
  EXPECT_DOUBLE_EQ(t2.w1, 0.75);
  EXPECT_EQ(t3.x0, 1);
  EXPECT_EQ(t3.x1, 1);
  // 2×2 {0, 1; 2, 3} (v = X + 2Y) up to 4×4: texel (1, 2) samples X = 0.25, Y = 0.75 → 1.75;
  // the corner (0, 0) is clamped to the corner value, (3, 3) likewise.
  const float src[4] = {0, 1, 2, 3};
  float dst[16];
  bilinear_upsample(src, 2, 2, 1, 4, 4, dst);
  EXPECT_FLOAT_EQ(dst[2 * 4 + 1], 1.75f);
  EXPECT_FLOAT_EQ(dst[0], 0.0f);
  EXPECT_FLOAT_EQ(dst[15], 3.0f);
  EXPECT_FLOAT_EQ(dst[1 * 4 + 2], 0.75f + 2 * 0.25f);
  // A size that does not divide: 5 texels from 3, the middle one at the middle texel's centre.
  const BilinearTap m = bilinear_tap(5, 3, 2);
  EXPECT_EQ(m.x0, 1);
  EXPECT_NEAR(m.w1, 0.0, 1e-12);
}

TEST(LowResPlanes, ProfileFieldIsChecked) {
  const std::string head = R"({"name": "t", "planes": {"iz": "bc6h", "dir": "bc5", "ratio": "bc4"})";
  EXPECT_EQ(profile_from_json(head + "}", "t.json").dir_ratio_scale, 1);
  EXPECT_EQ(profile_from_json(head + R"(, "dir_ratio_scale": 4})", "t.json").dir_ratio_scale, 4);
  for (const char* bad : {"3", "0", "\"2\"", "2.5", "-2", "8"}) {
    try {
      profile_from_json(head + ", \"dir_ratio_scale\": " + bad + "}", "t.json");
      ADD_FAILURE() << bad;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("t.json: dir_ratio_scale must be 1, 2 or 4"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(builtin_profile("pc-bc-half").dir_ratio_scale, 2);
  EXPECT_EQ(builtin_profile("pc-bc-quarter").dir_ratio_scale, 4);
  EXPECT_EQ(builtin_profile("pc-bc").dir_ratio_scale, 1);
}

TEST(LowResPlanes, IzIsPcBcsAndSidePlanesAreSmallerAndDecodeWithinConstraints) {
  const ShImage sh = scene(30, 18);  // sizes s does not divide
  PipelineOptions opt;
  opt.measure = Measure::Full;
  opt.measure_baselines = false;
  const PipelineResult full = run_conversion(sh, builtin_profile("pc-bc"), opt);
  for (const std::string name : {"pc-bc-half", "pc-bc-quarter"}) {
    SCOPED_TRACE(name);
    const Profile prof = builtin_profile(name);
    const int s = prof.dir_ratio_scale;
    const PipelineResult r = run_conversion(sh, prof, opt);
    ASSERT_TRUE(r.directional);
    const Plane& iz = plane_named(r, "iz");
    ASSERT_EQ(iz.texture.levels.size(), plane_named(full, "iz").texture.levels.size());
    for (size_t l = 0; l < iz.texture.levels.size(); ++l)
      EXPECT_EQ(iz.texture.levels[l].data, plane_named(full, "iz").texture.levels[l].data) << "level " << l;
    const uint32_t w0 = scaled_plane_size(30, s), h0 = scaled_plane_size(18, s);
    for (const char* side : {"dir", "ratio"}) {
      const Texture& t = plane_named(r, side).texture;
      ASSERT_EQ(t.levels.size(), full_mip_count(w0, h0)) << side;
      for (size_t l = 0; l < t.levels.size(); ++l) {
        EXPECT_EQ(t.levels[l].width, std::max(1u, w0 >> l)) << side;
        EXPECT_EQ(t.levels[l].height, std::max(1u, h0 >> l)) << side;
      }
    }
    // Every level decodes (those past the side chain's end read its last level) within the constraints.
    for (size_t l = 0; l < iz.texture.levels.size(); ++l) {
      const DecodedPlanes p = decode_planes(r.planes, false, int(l));
      ASSERT_EQ(p.width, int(iz.texture.levels[l].width));
      for (size_t i = 0; i < p.ratio.size(); ++i) {
        ASSERT_GE(p.ratio[i], 0.0f);
        ASSERT_LE(p.ratio[i], 1.0f);
      }
      for (const AhdLobe& lobe : lobes_from_planes(p, opt.fit.dz_min)) {
        ASSERT_GE(lobe.d[2], opt.fit.dz_min - 1e-9);
        for (int c = 0; c < 3; ++c) {
          ASSERT_GE(lobe.ca[c], 0.0);
          ASSERT_GE(lobe.cd[c], 0.0);
        }
      }
    }
    // The error is measured as an engine sees it, and stays finite and modest on a smooth scene.
    EXPECT_TRUE(std::isfinite(r.final_error.relative.p99));
    EXPECT_LT(r.final_error.relative.p99, 0.5);
  }
}

TEST(LowResPlanes, DecodeSamplesTheSmallPlanesBilinearly) {
  const ShImage sh = scene(16, 16);
  const PipelineResult r = run_conversion(sh, builtin_profile("pc-bc-half"), PipelineOptions{});
  const DecodedPlanes p = decode_planes(r.planes, false, 0);
  // By hand: ratio at texel (5, 10) of 16² from the 8² plane samples t = (5.5/2 − 0.5, 10.5/2 − 0.5)
  // = (2.25, 4.75): 0.75·0.25 of (2,4), 0.25·0.25 of (3,4), 0.75·0.75 of (2,5), 0.25·0.75 of (3,5).
  const ImageF ratio = decode_plane(plane_named(r, "ratio").texture.format, plane_named(r, "ratio").texture.levels[0]);
  ASSERT_EQ(ratio.width, 8);
  auto v = [&](int x, int y) { return double(ratio.at(x, y)[0]); };
  const double expect = 0.75 * 0.25 * v(2, 4) + 0.25 * 0.25 * v(3, 4) + 0.75 * 0.75 * v(2, 5) + 0.25 * 0.75 * v(3, 5);
  EXPECT_NEAR(p.ratio[(10 * 16 + 5) * 3], expect, 1e-6);
  // The direction: the uv sampled the same way, then decoded.
  const ImageF uv = decode_plane(plane_named(r, "dir").texture.format, plane_named(r, "dir").texture.levels[0]);
  float uvs[2];
  for (int c = 0; c < 2; ++c)
    uvs[c] = float(0.75 * 0.25 * uv.at(2, 4)[c] + 0.25 * 0.25 * uv.at(3, 4)[c] + 0.75 * 0.75 * uv.at(2, 5)[c] +
                   0.25 * 0.75 * uv.at(3, 5)[c]);
  float d[3];
  unit_uv_to_dir(uvs, d);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(p.d[(10 * 16 + 5) * 3 + c], d[c], 1e-5);
  // A side plane of a size no scale gives is refused.
  std::vector<Plane> bad = r.planes;
  for (Plane& pl : bad)
    if (pl.name == "ratio") pl.texture.levels[0].width = 7;
  EXPECT_THROW(decode_planes(bad, false, 0), Error);
}

TEST(LowResPlanes, BytesDoNotDependOnThreadsAndPackedPlaneWorks) {
  const ShImage sh = scene(40, 24);
  PipelineOptions one, two;
  one.threads = 1, two.threads = 2;
  const Profile prof = builtin_profile("pc-bc-half");
  const PipelineResult a = run_conversion(sh, prof, one), b = run_conversion(sh, prof, two);
  ASSERT_EQ(a.planes.size(), b.planes.size());
  for (size_t k = 0; k < a.planes.size(); ++k)
    for (size_t l = 0; l < a.planes[k].texture.levels.size(); ++l)
      EXPECT_EQ(a.planes[k].texture.levels[l].data, b.planes[k].texture.levels[l].data) << a.planes[k].name;
  const Profile packed = profile_from_json(
      R"({"name": "p", "planes": {"iz": "rgba16f", "dirratio": "rgba8"}, "dir_ratio_scale": 4})", "p.json");
  const PipelineResult r = run_conversion(sh, packed, one);
  EXPECT_EQ(plane_named(r, "dirratio").texture.levels[0].width, 10u);
  const DecodedPlanes p = decode_planes(r.planes, false, 0);
  for (float v : p.ratio) ASSERT_TRUE(v >= 0.0f && v <= 1.0f);
}

TEST(LowResPlanes, SweepsLowerTheBilinearObjective) {
  const ShImage sh = scene(24, 24);
  FitOptions fit;
  fit.direction_fit = DirectionFit::Refined;
  const LowResDirections dirs = lowres_directions(sh, 12, 12, fit, 1);
  std::vector<float> d(sh.texels() * 3), iz(sh.texels() * 3);
  bilinear_upsample(dirs.d.data(), 12, 12, 3, 24, 24, d.data());
  for (size_t i = 0; i < sh.texels(); ++i) {
    IrradiancePoly p[3];
    local_polys(sh, i, p);
    const AhdFit f = fit_texel(p, fit);
    for (int c = 0; c < 3; ++c) iz[i * 3 + c] = f.iz[c];
  }
  const RatioQuadratics q = ratio_quadratics(sh, iz.data(), d.data(), fit, 1);
  std::vector<float> ratio = lowres_box_ratio(q, 12, 12);
  const double before = lowres_ratio_objective(q, 12, 12, ratio);
  std::vector<float> two = ratio;
  lowres_ratio_sweeps(q, 12, 12, ratio, 4, 1);
  lowres_ratio_sweeps(q, 12, 12, two, 4, 2);
  EXPECT_EQ(ratio, two);  // thread-count independent
  const double after = lowres_ratio_objective(q, 12, 12, ratio);
  EXPECT_LT(after, before);
  for (float v : ratio) ASSERT_TRUE(v >= 0.0f && v <= 1.0f);
}

TEST(LowResPlanes, ManifestAcceptsScaledSidePlanesOnly) {
  auto manifest = [](uint32_t dw, uint32_t dh, uint32_t dl) {
    Manifest m;
    m.profile = "pc-bc-half";
    m.container = "ktx2";
    m.width = 30, m.height = 18, m.levels = 5;
    const std::string h(64, 'a');
    m.planes.push_back({"iz", "a.iz.ktx2", PixelFormat::BC6H_UFLOAT, 30, 18, 5, 10, h});
    m.planes.push_back({"dir", "a.dir.ktx2", PixelFormat::BC5_UNORM, dw, dh, dl, 10, h});
    m.planes.push_back({"ratio", "a.ratio.ktx2", PixelFormat::BC4_UNORM, dw, dh, dl, 10, h});
    return manifest_to_json(m);
  };
  EXPECT_NO_THROW(manifest_from_json(manifest(15, 9, 4), "m.json"));  // s = 2: its chain is 4 long
  EXPECT_NO_THROW(manifest_from_json(manifest(8, 5, 4), "m.json"));   // s = 4
  EXPECT_NO_THROW(manifest_from_json(manifest(30, 18, 5), "m.json"));
  EXPECT_THROW(manifest_from_json(manifest(15, 9, 5), "m.json"), Error);  // more levels than 15×9 has
  EXPECT_THROW(manifest_from_json(manifest(10, 6, 3), "m.json"), Error);  // s = 3
  EXPECT_THROW(manifest_from_json(manifest(15, 5, 3), "m.json"), Error);  // two scales
}

namespace {

// Σ over covered texels of the hemisphere MSE of the full-res texels decoded from I_z and the
// bilinearly sampled low-res uv and ratio (luminance form), as an engine decodes them.
double sampled_error(const ShImage& sh, const std::vector<float>& iz, const std::vector<float>& uv,
                     const std::vector<float>& ratio, int lw, int lh, double dz_min) {
  std::vector<float> uvf(sh.texels() * 2), rf(sh.texels());
  bilinear_upsample(uv.data(), lw, lh, 2, sh.width, sh.height, uvf.data());
  bilinear_upsample(ratio.data(), lw, lh, 1, sh.width, sh.height, rf.data());
  double sum = 0;
  for (size_t i = 0; i < sh.texels(); ++i) {
    if (!sh.coverage[i]) continue;
    float d[3];
    unit_uv_to_dir(&uvf[i * 2], d);
    const float r3[3] = {rf[i], rf[i], rf[i]};
    double ca[3], cd[3], u[3];
    decode_colours(&iz[i * 3], d, r3, dz_min, ca, cd, u);
    IrradiancePoly p[3];
    local_polys(sh, i, p);
    for (int c = 0; c < 3; ++c) sum += hemisphere_mse(hemisphere_moments(p[c], u), ca[c], cd[c]);
  }
  return sum;
}

}  // namespace

TEST(LowResPlanes, DirectionSweepsLowerTheSampledErrorAtAnyThreadCount) {
  const ShImage sh = scene(24, 20);
  FitOptions fit;
  fit.direction_fit = DirectionFit::Refined;
  const int lw = 6, lh = 5;
  const LowResDirections dirs = lowres_directions(sh, lw, lh, fit, 1);
  std::vector<float> uv(size_t(lw) * lh * 2), iz(sh.texels() * 3), d(sh.texels() * 3), uvf(sh.texels() * 2);
  for (size_t k = 0; k < size_t(lw) * lh; ++k) {  // every box is covered in the analytic scene
    ASSERT_TRUE(dirs.coverage[k]);
    // The hemi-octahedral uv of the unit d (d_z ≥ dz_min > 0): p = d.xy / |d|₁, uv = (px+py, px−py).
    const float* dk = &dirs.d[k * 3];
    const double l1 = std::abs(dk[0]) + std::abs(dk[1]) + std::abs(dk[2]);
    const double px = dk[0] / l1, py = dk[1] / l1;
    uv[k * 2] = float((px + py) * 0.5 + 0.5), uv[k * 2 + 1] = float((px - py) * 0.5 + 0.5);
  }
  for (size_t i = 0; i < sh.texels(); ++i) {
    IrradiancePoly p[3];
    local_polys(sh, i, p);
    const AhdFit f = fit_texel(p, fit);
    for (int c = 0; c < 3; ++c) iz[i * 3 + c] = f.iz[c];
  }
  bilinear_upsample(uv.data(), lw, lh, 2, sh.width, sh.height, uvf.data());
  for (size_t i = 0; i < sh.texels(); ++i) unit_uv_to_dir(&uvf[i * 2], &d[i * 3]);
  const std::vector<float> ratio = lowres_box_ratio(ratio_quadratics(sh, iz.data(), d.data(), fit, 1), lw, lh);
  const double before = sampled_error(sh, iz, uv, ratio, lw, lh, fit.dz_min);
  std::vector<float> uv1 = uv, r1 = ratio, uv2 = uv, r2 = ratio;
  lowres_direction_sweeps(sh, iz.data(), lw, lh, uv1, r1, fit, 3, 1);
  lowres_direction_sweeps(sh, iz.data(), lw, lh, uv2, r2, fit, 3, 2);
  EXPECT_EQ(uv1, uv2);
  EXPECT_EQ(r1, r2);
  EXPECT_NE(uv1, uv);  // it moved
  const double after = sampled_error(sh, iz, uv1, r1, lw, lh, fit.dz_min);
  EXPECT_LT(after, before);
  for (float v : uv1) ASSERT_TRUE(v >= 0.0f && v <= 1.0f);
  for (float v : r1) ASSERT_TRUE(v >= 0.0f && v <= 1.0f);
}
