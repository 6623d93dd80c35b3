// SH-domain mip chains: sizes, filter weights, I_z linearity per level (SH and fitted AHD),
// world-space normals, thread independence, independence from gutter garbage, per-level error.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>

#include "fit_bits.h"
#include "core/error.h"
#include "fit/fit_image.h"
#include "fit/hemisphere_error.h"
#include "mips/mips.h"
#include "sample/analytic_baker.h"

using namespace ahd;

namespace {

ShImage mip_scene(int w, int h, int coeffs) {
  BakerOptions bo;
  bo.width = w;
  bo.height = h;
  bo.coeffs = coeffs;
  bo.area_samples = 3;
  return bake_analytic_scene(bo);
}

// A synthetic atlas: rectangular charts separated by gutters, smooth SH with positive I_z inside
// each chart (different lighting per chart), huge finite garbage in the gutters.
// world = true adds strongly curved world-space normals (SH then read as world space).
ShImage atlas(int w, int h, int coeffs, uint32_t seed, bool world = false, bool full = false) {
  ShImage img = make_sh_image(w, h, coeffs);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  struct Rect {
    int x0, y0, x1, y1;
    double base[27], gx[27], gy[27];
  };
  std::vector<Rect> charts;
  const int cols = 3, rows = 2;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      Rect q;
      // Gutters of 2..4 texels; odd chart sizes and positions on purpose.
      q.x0 = full ? 0 : c * w / cols + 2 + (r + c) % 3;
      q.x1 = full ? w : (c + 1) * w / cols - 1 - (c % 2);
      q.y0 = full ? 0 : r * h / rows + 2 + c % 2;
      q.y1 = full ? h : (r + 1) * h / rows - 2;
      for (int k = 0; k < 27; ++k) {
        const bool dc = k / 3 == 0;
        q.base[k] = dc ? 1.0 + 0.5 * u(rng) : 0.12 * u(rng);
        q.gx[k] = 0.004 * u(rng);
        q.gy[k] = 0.004 * u(rng);
      }
      charts.push_back(q);
      if (full) break;
    }
  if (full) charts.resize(1);
  std::uniform_real_distribution<float> garbage(-1e6f, 1e6f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const Rect* in = nullptr;
      for (const Rect& q : charts)
        if (x >= q.x0 && x < q.x1 && y >= q.y0 && y < q.y1) in = &q;
      img.coverage[i] = in ? 1 : 0;
      float* t = img.texel(i);
      for (int k = 0; k < coeffs * 3; ++k)
        t[k] = in ? float(in->base[k] + in->gx[k] * x + in->gy[k] * y + 0.03 * std::sin(0.7 * x + k) * std::cos(0.5 * y))
                  : garbage(rng);
    }
  if (world) {
    img.normals.resize(img.texels() * 3);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        // A bumpy surface: the normal turns by up to ~70° across a few texels.
        const double th = 1.2 * std::sin(0.9 * x) * std::cos(0.4 * y), ph = 0.8 * x + 0.3 * y;
        float* n = &img.normals[(size_t(y) * w + x) * 3];
        n[0] = float(std::sin(th) * std::cos(ph));
        n[1] = float(std::sin(th) * std::sin(ph));
        n[2] = float(std::cos(th));
      }
  }
  return img;
}

// I_z of texel i, channel c: E(z) of the local-frame irradiance polynomial.
double iz_of(const ShImage& img, size_t i, int c) {
  IrradiancePoly p[3];
  local_polys(img, i, p);
  return p[c].e0 + p[c].e[2] + p[c].q[2][2];
}

// Worst relative deviation, over covered texels of every level ≥ 1, between the level's I_z (from
// its SH, and from the fit of its SH) and the coverage-weighted mean of the finer level's I_z under
// the documented taps. Also checks the coverage rule.
struct Linearity {
  double sh = 0, fit = 0;
};
Linearity check_linearity(const std::vector<ShImage>& chain) {
  Linearity worst;
  for (size_t l = 1; l < chain.size(); ++l) {
    const ShImage &f = chain[l - 1], &g = chain[l];
    const AhdImage fit = fit_image(g, FitOptions{}, 2);
    for (int Y = 0; Y < g.height; ++Y)
      for (int X = 0; X < g.width; ++X) {
        const size_t o = size_t(Y) * g.width + X;
        MipTap tx[3], ty[3];
        const int nx = mip_taps(f.width, X, tx), ny = mip_taps(f.height, Y, ty);
        double ref[3] = {0, 0, 0}, ws = 0;
        bool any = false;
        for (int b = 0; b < ny; ++b)
          for (int a = 0; a < nx; ++a) {
            const size_t i = size_t(ty[b].index) * f.width + tx[a].index;
            if (!f.coverage[i]) continue;
            any = true;
            const double wt = tx[a].weight * ty[b].weight;
            for (int c = 0; c < 3; ++c) ref[c] += wt * iz_of(f, i, c);
            ws += wt;
          }
        EXPECT_EQ(g.coverage[o] != 0, any) << "level " << l << " texel " << X << "," << Y;
        if (!any) continue;
        for (int c = 0; c < 3; ++c) {
          const double r = ref[c] / ws;
          EXPECT_GT(r, 0.0);
          worst.sh = std::max(worst.sh, std::fabs(iz_of(g, o, c) - r) / r);
          worst.fit = std::max(worst.fit, std::fabs(double(fit.texel(o).iz[c]) - r) / r);
        }
      }
  }
  return worst;
}

}  // namespace

TEST(Mips, TapsSumToOneAndWeighEverySourceTexelEqually) {
  for (int n = 1; n <= 41; ++n) {
    const int m = std::max(1, n / 2);
    std::vector<double> total(size_t(n), 0.0);
    for (int i = 0; i < m; ++i) {
      MipTap t[3];
      const int k = mip_taps(n, i, t);
      double s = 0;
      for (int j = 0; j < k; ++j) {
        ASSERT_GE(t[j].index, 0);
        ASSERT_LT(t[j].index, n);
        ASSERT_GT(t[j].weight, 0.0);
        s += t[j].weight;
        total[size_t(t[j].index)] += t[j].weight;
      }
      EXPECT_NEAR(s, 1.0, 1e-12) << "n=" << n << " i=" << i;
    }
    // Nothing dropped, nothing favoured: each source texel weighs n_dst/n_src in total.
    for (int x = 0; x < n; ++x) EXPECT_NEAR(total[size_t(x)], double(m) / n, 1e-12) << "n=" << n << " x=" << x;
  }
}

TEST(Mips, ChainSizesFollowD3DVulkanRule) {
  struct Case {
    int w, h;
    std::vector<std::pair<int, int>> sizes;
  };
  const std::vector<Case> cases = {
      {64, 64, {{64, 64}, {32, 32}, {16, 16}, {8, 8}, {4, 4}, {2, 2}, {1, 1}}},
      {37, 23, {{37, 23}, {18, 11}, {9, 5}, {4, 2}, {2, 1}, {1, 1}}},
      {1, 13, {{1, 13}, {1, 6}, {1, 3}, {1, 1}}},
      {7, 1, {{7, 1}, {3, 1}, {1, 1}}},
      {5, 40, {{5, 40}, {2, 20}, {1, 10}, {1, 5}, {1, 2}, {1, 1}}},
      {1, 1, {{1, 1}}},
  };
  for (const Case& cs : cases) {
    const ShImage img = atlas(cs.w, cs.h, 4, 3, false, true);
    const std::vector<ShImage> chain = build_sh_mips(img, 0, 2);
    ASSERT_EQ(chain.size(), cs.sizes.size()) << cs.w << "x" << cs.h;
    EXPECT_EQ(mip_level_count(cs.w, cs.h), int(cs.sizes.size()));
    for (size_t l = 0; l < chain.size(); ++l) {
      EXPECT_EQ(chain[l].width, cs.sizes[l].first);
      EXPECT_EQ(chain[l].height, cs.sizes[l].second);
      EXPECT_EQ(mip_size(cs.w, int(l)), cs.sizes[l].first);
      EXPECT_EQ(chain[l].data.size(), chain[l].texels() * 4 * 3);
      EXPECT_EQ(chain[l].coverage.size(), chain[l].texels());
      for (float v : chain[l].data) ASSERT_TRUE(std::isfinite(v));
    }
  }
  const ShImage img = atlas(37, 23, 9, 3, false, true);
  EXPECT_EQ(build_sh_mips(img, 2, 2).size(), 2u);
  EXPECT_EQ(build_sh_mips(img, 1, 2).size(), 1u);
  EXPECT_EQ(build_sh_mips(img, 99, 2).size(), 6u);
}

TEST(Mips, IzIsLinearAtEveryLevelForShAndFit) {
  struct Case {
    const char* name;
    ShImage img;
  };
  std::vector<Case> cases;
  for (int coeffs : {4, 9}) {
    cases.push_back({"analytic 64x64", mip_scene(64, 64, coeffs)});
    cases.push_back({"analytic 37x23", mip_scene(37, 23, coeffs)});
    cases.push_back({"atlas 53x41", atlas(53, 41, coeffs, 11)});
    cases.push_back({"atlas 1x29", atlas(1, 29, coeffs, 12, false, true)});
  }
  for (const Case& cs : cases) {
    const std::vector<ShImage> chain = build_sh_mips(cs.img, 0, 2);
    const Linearity w = check_linearity(chain);
    std::printf("  I_z linearity %-15s L%d: worst rel SH %.2e, fit %.2e over %zu levels\n", cs.name,
                cs.img.coeffs == 4 ? 1 : 2, w.sh, w.fit, chain.size());
    EXPECT_LE(w.sh, 1e-6) << cs.name;
    EXPECT_LE(w.fit, 1e-6) << cs.name;
  }
}

// Independent of mip_taps: on a fully covered image every source texel weighs the same, so the
// mean I_z over the whole level is the same at every level.
TEST(Mips, FullyCoveredMeanIzIsPreserved) {
  for (auto [w, h] : {std::pair{37, 23}, {16, 9}, {1, 13}}) {
    const std::vector<ShImage> chain = build_sh_mips(atlas(w, h, 9, 5, false, true), 0, 2);
    auto mean = [](const ShImage& g, int c) {
      double s = 0;
      for (size_t i = 0; i < g.texels(); ++i) s += iz_of(g, i, c);
      return s / double(g.texels());
    };
    for (int c = 0; c < 3; ++c) {
      const double m0 = mean(chain[0], c);
      for (size_t l = 1; l < chain.size(); ++l) EXPECT_NEAR(mean(chain[l], c), m0, 1e-6 * m0) << w << "x" << h << " level " << l;
    }
  }
}

TEST(Mips, WorldSpaceRotateThenAverageKeepsIzLinear) {
  for (int coeffs : {4, 9}) {
    const ShImage img = atlas(45, 30, coeffs, 21, true);
    const std::vector<ShImage> chain = build_sh_mips(img, 0, 2);
    for (size_t l = 1; l < chain.size(); ++l) {
      // Local-frame SH flagged by normals = +z, which must read back exactly as stored.
      ASSERT_EQ(chain[l].normals.size(), chain[l].texels() * 3);
      for (size_t i = 0; i < chain[l].texels(); ++i) {
        ASSERT_EQ(chain[l].normals[i * 3 + 2], 1.0f);
        IrradiancePoly p[3];
        local_polys(chain[l], i, p);
        for (int c = 0; c < 3; ++c) {
          const IrradiancePoly raw = irradiance_poly(chain[l].texel(i) + c, coeffs, 3);
          ASSERT_EQ(p[c].e0, raw.e0);
          for (int a = 0; a < 3; ++a) {
            ASSERT_EQ(p[c].e[a], raw.e[a]);
            for (int b = 0; b < 3; ++b) ASSERT_EQ(p[c].q[a][b], raw.q[a][b]);
          }
        }
      }
    }
    const Linearity w = check_linearity(chain);
    std::printf("  I_z linearity world-space L%d (rotate, then average): SH %.2e, fit %.2e\n", coeffs == 4 ? 1 : 2,
                w.sh, w.fit);
    EXPECT_LE(w.sh, 1e-6);
    EXPECT_LE(w.fit, 1e-6);
  }
}

// A 1×1 world-space image mips to itself rotated into its local frame: the whole local irradiance
// polynomial (not only I_z) must survive the SH → polynomial → SH round trip, for any normal.
TEST(Mips, WorldToLocalRotationIsExact) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    ShImage img = make_sh_image(1, 1, 9);
    for (float& v : img.data) v = float(u(rng));
    double n[3] = {u(rng), u(rng), u(rng)};
    if (trial == 0) n[0] = 0, n[1] = 0, n[2] = 1;
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    img.normals = {float(n[0] / len), float(n[1] / len), float(n[2] / len)};
    const ShImage out = downsample_sh(img, 1);
    ASSERT_EQ(out.normals, (std::vector<float>{0.0f, 0.0f, 1.0f}));
    IrradiancePoly a[3], b[3];
    local_polys(img, 0, a);
    local_polys(out, 0, b);
    for (int k = 0; k < 20; ++k) {
      double d[3] = {u(rng), u(rng), u(rng)};
      const double l = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      for (double& x : d) x /= l;
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(eval_irradiance(b[c], d), eval_irradiance(a[c], d), 1e-5);
    }
  }
}

// The documented alternative keeps world space; on a curved chart its I_z is visibly not the mean
// of the finer I_z — the reason RotateThenAverage is the default.
TEST(Mips, WorldSpaceAverageThenRotateDiffersOnCurvedCharts) {
  const ShImage img = atlas(45, 30, 9, 21, true);
  const std::vector<ShImage> chain = build_sh_mips(img, 0, 2, NormalRule::AverageThenRotate);
  for (size_t l = 1; l < chain.size(); ++l) {
    ASSERT_EQ(chain[l].normals.size(), chain[l].texels() * 3);
    for (size_t i = 0; i < chain[l].texels(); ++i) {
      if (!chain[l].coverage[i]) continue;
      const float* n = &chain[l].normals[i * 3];
      EXPECT_NEAR(n[0] * n[0] + n[1] * n[1] + n[2] * n[2], 1.0, 1e-5);
    }
  }
  const Linearity w = check_linearity(chain);
  std::printf("  I_z deviation world-space (average, then rotate): worst rel %.2e\n", w.sh);
  EXPECT_GT(w.sh, 1e-3);
}

// Two fitted texels with the same bits in every field (field by field: padding is no data).
TEST(Mips, ThreadCountDoesNotChangeTheChain) {
  for (bool world : {false, true}) {
    const ShImage img = atlas(61, 47, 9, 4, world);
    const std::vector<ShImage> a = build_sh_mips(img, 0, 1), b = build_sh_mips(img, 0, 2);
    ASSERT_EQ(a.size(), b.size());
    for (size_t l = 0; l < a.size(); ++l) {
      EXPECT_EQ(a[l].data, b[l].data);
      EXPECT_EQ(a[l].coverage, b[l].coverage);
      EXPECT_EQ(a[l].normals, b[l].normals);
    }
  }
  const ShImage img = mip_scene(40, 40, 9);
  const auto x = fit_mip_chain(img, FitOptions{}, 0, 1), y = fit_mip_chain(img, FitOptions{}, 0, 2);
  ASSERT_EQ(x.size(), y.size());
  for (size_t l = 0; l < x.size(); ++l)
    for (size_t i = 0; i < x[l].ahd.size(); ++i)
      ASSERT_TRUE(same_fit_bits(x[l].ahd.texel(i), y[l].ahd.texel(i))) << l << " " << i;
}

// Gutter garbage must influence nothing: not the coarse SH, not the fit, not the dilated values.
TEST(Mips, ChainIgnoresUncoveredInput) {
  ShImage a = atlas(53, 41, 9, 11), b = a;
  std::mt19937 rng(77);
  std::uniform_real_distribution<float> g(-3e7f, 3e7f);
  for (size_t i = 0; i < b.texels(); ++i)
    if (!b.coverage[i])
      for (int k = 0; k < 27; ++k) b.texel(i)[k] = g(rng);
  ASSERT_NE(a.data, b.data);
  const auto x = fit_mip_chain(a, FitOptions{}, 0, 2), y = fit_mip_chain(b, FitOptions{}, 0, 2);
  for (size_t l = 0; l < x.size(); ++l) {
    if (l > 0) {
      EXPECT_EQ(x[l].sh.data, y[l].sh.data) << "level " << l;
    }
    for (size_t i = 0; i < x[l].ahd.size(); ++i)
      ASSERT_TRUE(same_fit_bits(x[l].ahd.texel(i), y[l].ahd.texel(i))) << l << " " << i;
  }
}

// Per-level accuracy: the AHD fit of each mip's SH against that mip's SH, and dilation statistics.
TEST(Mips, FitMipChainErrorPerLevel) {
  for (auto [w, h] : {std::pair{64, 64}, {37, 23}}) {
    const ShImage img = mip_scene(w, h, 9);
    std::vector<FitStats> fs;
    std::vector<DilateStats> ds;
    const FitOptions opt;
    const auto chain = fit_mip_chain(img, opt, 0, 2, &fs, &ds);
    ASSERT_EQ(int(chain.size()), mip_level_count(w, h));
    ASSERT_EQ(fs.size(), chain.size());
    ASSERT_EQ(ds.size(), chain.size());
    std::printf("  %dx%d analytic scene, L2: level  size    covered guard filled rings  rel.mean  rel.p99   rel.max   Iz.max\n", w, h);
    for (size_t l = 0; l < chain.size(); ++l) {
      const FittedLevel& lv = chain[l];
      std::vector<AhdLobe> lobes(lv.ahd.size());
      for (size_t i = 0; i < lobes.size(); ++i)
        for (int c = 0; c < 3; ++c) {
          lobes[i].ca[c] = fitted_ca(lv.ahd.texel(i), c);
          lobes[i].cd[c] = fitted_cd(lv.ahd.texel(i), c);
          lobes[i].d[c] = lv.ahd.texel(i).d[c];
        }
      const ErrorReport e = measure_error(lv.sh, lobes, 2);
      std::printf("  %33zu %4dx%-4d %6zu %5zu %6zu %5d  %.2e  %.2e  %.2e  %.1e\n", l, lv.sh.width, lv.sh.height,
                  ds[l].covered, ds[l].guard, ds[l].filled, ds[l].rings, e.relative.mean, e.relative.p99,
                  e.relative.max, e.normal_rel.max);
      EXPECT_EQ(ds[l].covered + ds[l].filled, lv.sh.texels());
      EXPECT_EQ(e.texels, ds[l].covered);
      EXPECT_EQ(e.negative, 0u);
      EXPECT_TRUE(std::isfinite(e.relative.max));
      EXPECT_LT(e.relative.mean, 0.25) << "level " << l;
      EXPECT_LT(e.relative.max, 1.0) << "level " << l;
      EXPECT_LT(e.normal_rel.max, 1e-5) << "level " << l;
      for (size_t i = 0; i < lv.ahd.size(); ++i)
        for (int c = 0; c < 3; ++c) {
          const AhdFit f = lv.ahd.texel(i);
          ASSERT_TRUE(std::isfinite(f.iz[c]) && std::isfinite(fitted_ca(f, c)) && std::isfinite(fitted_cd(f, c)));
          ASSERT_GE(f.iz[c], 0.0f);
        }
    }
  }
}

TEST(Mips, RejectsMalformedImages) {
  ShImage img = make_sh_image(4, 4, 9);
  img.coverage.resize(3);
  EXPECT_THROW(build_sh_mips(img, 0, 1), Error);
  ShImage n = make_sh_image(4, 4, 9);
  n.normals.resize(5);
  EXPECT_THROW(build_sh_mips(n, 0, 1), Error);
  EXPECT_THROW(build_sh_mips(make_sh_image(4, 4, 9), -1, 1), Error);
}

// L0 images (plain lightmaps) are fitted as their I_z plane alone (fit_ambient_level): it must hold
// bit for bit the iz of the full fit's texels, dilated texels included, with the same counts.
TEST(Mips, AmbientLevelHoldsTheFullFitsIz) {
  for (bool world : {false, true}) {
    ShImage img = atlas(37, 29, 1, 5, world);
    img.texel(40)[1] = -0.25f;  // SH ringing: negative I_z, clamped and counted
    img.texel(41)[0] = -0.0f;   // the sign of a zero must come out as the full fit's
    for (int k = 0; k < 3; ++k) img.texel(42)[k] = 0.0f;  // black
    // Not finite (readers replace these; the fit stays total when called directly).
    img.texel(43)[0] = std::numeric_limits<float>::quiet_NaN();
    img.texel(44)[1] = std::numeric_limits<float>::infinity();
    img.texel(45)[2] = -std::numeric_limits<float>::infinity();
    for (size_t i = 40; i <= 45; ++i) img.coverage[i] = 1;
    FitStats fa, ff;
    DilateStats da, df;
    const FittedLevel a = fit_ambient_level(ShImage(img), FitOptions{}, 2, &fa, &da);
    const FittedLevel f = fit_level(ShImage(img), FitOptions{}, 2, &ff, &df);
    ASSERT_TRUE(a.ahd.empty());
    ASSERT_EQ(a.sh.texels(), f.ahd.size());
    for (size_t i = 0; i < f.ahd.size(); ++i) {
      const AhdFit t = fitted_texel(a, i);
      ASSERT_EQ(std::memcmp(t.iz, f.ahd.texel(i).iz, sizeof t.iz), 0) << world << " " << i;
      ASSERT_EQ(std::memcmp(t.d, f.ahd.texel(i).d, sizeof t.d), 0) << i;
      ASSERT_EQ(std::memcmp(t.ratio, f.ahd.texel(i).ratio, sizeof t.ratio), 0) << i;
      // Covered texels keep their SH (the next level is filtered from it).
      if (img.coverage[i]) ASSERT_EQ(std::memcmp(a.sh.texel(i), img.texel(i), 3 * sizeof(float)), 0) << i;
    }
    EXPECT_EQ(fa.covered, ff.covered);
    EXPECT_EQ(fa.no_direction, ff.no_direction);
    EXPECT_EQ(fa.negative_iz, ff.negative_iz);
    EXPECT_EQ(fa.black, ff.black);
    EXPECT_GE(fa.negative_iz, 1u);
    EXPECT_GE(fa.black, 1u);
    EXPECT_EQ(da.filled, df.filled);
    EXPECT_EQ(da.rings, df.rings);
  }
  EXPECT_THROW(fit_ambient_level(atlas(8, 8, 9, 1), FitOptions{}, 1), Error);
}
