// Dilation: garbage independence under GPU-style bilinear sampling, no bleeding across gutters,
// reach, convexity, thread independence, the AhdImage form and the coverage plane.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>

#include "core/error.h"
#include "fit/fit_image.h"
#include "codecs/bc6h/bc6h_codec.h"
#include "codecs/octahedral.h"
#include "fit_bits.h"
#include "mips/dilate.h"
#include "sample/analytic_baker.h"

using namespace ahd;

namespace {

struct Planes {
  int w, h;
  std::vector<uint8_t> coverage;
  ImageF iz, uv, ratio;  // 3, 2 and 1 channels, as the pipeline stores them
};

// Several rectangular charts with gutters of ≥ 2 texels and smooth per-chart values.
std::vector<uint8_t> chart_coverage(int w, int h, int* charts = nullptr, std::vector<int>* id = nullptr) {
  std::vector<uint8_t> cov(size_t(w) * h, 0);
  if (id) id->assign(cov.size(), -1);
  int k = 0;
  for (int y0 = 1; y0 + 4 <= h; y0 += 11)
    for (int x0 = 2; x0 + 4 <= w; x0 += 13, ++k) {
      const int x1 = std::min(w, x0 + 7 + k % 4), y1 = std::min(h, y0 + 6 + k % 3);  // gutters 2..6
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
          cov[size_t(y) * w + x] = 1;
          if (id) (*id)[size_t(y) * w + x] = k;
        }
    }
  if (charts) *charts = k;
  return cov;
}

Planes synthetic(int w, int h) {
  Planes p{w, h, chart_coverage(w, h), ImageF(w, h, 3), ImageF(w, h, 2), ImageF(w, h, 1)};
  if (w < 6)  // too narrow for the rectangles: charts are bands of rows 4..8 and 12..14
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) p.coverage[size_t(y) * w + x] = (y >= 4 && y < 9) || (y >= 12 && y < 15);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < 3; ++c) p.iz.at(x, y)[c] = float(2.0 + std::sin(0.3 * x + c) * std::cos(0.2 * y) + 0.5 * c);
      p.uv.at(x, y)[0] = float(0.5 + 0.4 * std::sin(0.21 * x + 0.1 * y));
      p.uv.at(x, y)[1] = float(0.5 + 0.4 * std::cos(0.17 * y - 0.05 * x));
      p.ratio.at(x, y)[0] = float(0.5 + 0.45 * std::sin(0.13 * (x + y)));
    }
  return p;
}

void fill_garbage(ImageF& img, const std::vector<uint8_t>& cov, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> g(-1e7f, 1e7f);
  for (size_t i = 0; i < cov.size(); ++i)
    if (!cov[i])
      for (int c = 0; c < img.channels; ++c) img.data[i * img.channels + c] = g(rng);
}

// GPU bilinear with clamp-to-edge, at texel coordinates (x, y) where texel centres are integers.
void bilinear(const ImageF& img, double x, double y, double* out) {
  const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
  const double fx = x - x0, fy = y - y0;
  auto cl = [](int v, int n) { return std::clamp(v, 0, n - 1); };
  const float* a = img.at(cl(x0, img.width), cl(y0, img.height));
  const float* b = img.at(cl(x0 + 1, img.width), cl(y0, img.height));
  const float* c = img.at(cl(x0, img.width), cl(y0 + 1, img.height));
  const float* d = img.at(cl(x0 + 1, img.width), cl(y0 + 1, img.height));
  for (int k = 0; k < img.channels; ++k)
    out[k] = (1 - fy) * ((1 - fx) * a[k] + fx * b[k]) + fy * ((1 - fx) * c[k] + fx * d[k]);
}

// Worst relative difference of bilinear samples on a 5×5 grid within ±0.5 texel of every covered
// texel's centre.
double footprint_difference(const ImageF& a, const ImageF& b, const std::vector<uint8_t>& cov) {
  double worst = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      if (!cov[size_t(y) * a.width + x]) continue;
      for (int j = 0; j < 5; ++j)
        for (int i = 0; i < 5; ++i) {
          double sa[16], sb[16];
          bilinear(a, x - 0.5 + 0.25 * i, y - 0.5 + 0.25 * j, sa);
          bilinear(b, x - 0.5 + 0.25 * i, y - 0.5 + 0.25 * j, sb);
          for (int c = 0; c < a.channels; ++c)
            worst = std::max(worst, std::fabs(sa[c] - sb[c]) / std::max(std::fabs(sa[c]), 1e-6));
        }
    }
  return worst;
}

}  // namespace

TEST(Dilate, BilinearInsideChartsIgnoresGutterGarbage) {
  for (auto [w, h] : {std::pair{64, 64}, {37, 23}, {1, 17}}) {
    const Planes p = synthetic(w, h);
    for (const ImageF* src : {&p.iz, &p.uv, &p.ratio}) {
      ImageF a = *src, b = *src;
      fill_garbage(a, p.coverage, 1);
      fill_garbage(b, p.coverage, 2);
      // Sensitivity of the measure: without dilation the garbage shows through the footprints.
      if (w > 1) {
        EXPECT_GT(footprint_difference(a, b, p.coverage), 1.0);
      }
      DilateStats sa, sb;
      dilate(a, p.coverage, 2, &sa);
      dilate(b, p.coverage, 1, &sb);
      for (float v : a.data) ASSERT_TRUE(std::isfinite(v) && std::fabs(v) < 100.0f) << "every texel reached";
      const double diff = footprint_difference(a, b, p.coverage);
      EXPECT_LE(diff, 1e-4) << w << "x" << h;
      EXPECT_EQ(sa.rings, sb.rings);
      EXPECT_EQ(sa.guard, sb.guard);
      if (src == &p.iz)
        std::printf("  %dx%d atlas: covered %zu, guard texels %zu, filled %zu, rings %d, footprint diff %.1e\n", w, h,
                    sa.covered, sa.guard, sa.filled, sa.rings, diff);
    }
  }
}

// The same on the analytic scene's fitted planes, as the pipeline stores them (d as the
// hemi-octahedral uv in [0,1]²).
TEST(Dilate, AnalyticScenePlanesIgnoreGutterGarbage) {
  for (auto [w, h] : {std::pair{64, 64}, {37, 23}}) {
    BakerOptions bo;
    bo.width = w;
    bo.height = h;
    bo.area_samples = 3;
    const ShImage sh = bake_analytic_scene(bo);
    const AhdImage fit = fit_image(sh, FitOptions{}, 2);
    ImageF iz(w, h, 3), uv(w, h, 2), ratio(w, h, 1);
    for (size_t i = 0; i < sh.texels(); ++i) {
      const AhdFit f = fit.texel(i);
      for (int c = 0; c < 3; ++c) iz.data[i * 3 + c] = f.iz[c];
      const double d[3] = {f.d[0], f.d[1], f.d[2]};
      double e[2];
      hemi_oct_encode(d, e);
      uv.data[i * 2] = float(e[0] * 0.5 + 0.5);
      uv.data[i * 2 + 1] = float(e[1] * 0.5 + 0.5);
      ratio.data[i] = f.ratio[0];
    }
    for (const ImageF* src : {&iz, &uv, &ratio}) {
      ImageF a = *src, b = *src;
      fill_garbage(a, sh.coverage, 11);
      fill_garbage(b, sh.coverage, 12);
      EXPECT_GT(footprint_difference(a, b, sh.coverage), 1.0);
      DilateStats st;
      dilate(a, sh.coverage, 2, &st);
      dilate(b, sh.coverage, 1);
      const double diff = footprint_difference(a, b, sh.coverage);
      EXPECT_LE(diff, 1e-4);
      EXPECT_GT(st.guard, 0u);
      if (src == &iz)
        std::printf("  analytic %dx%d: covered %zu, guard texels %zu, filled %zu, rings %d, footprint diff %.1e\n", w,
                    h, st.covered, st.guard, st.filled, st.rings, diff);
    }
  }
}

TEST(Dilate, NoBleedingAcrossGuttersOfTwoTexels) {
  const int w = 70, h = 40;
  int charts = 0;
  std::vector<int> id;
  const std::vector<uint8_t> cov = chart_coverage(w, h, &charts, &id);
  ASSERT_GE(charts, 6);
  ImageF img(w, h, 1);
  for (size_t i = 0; i < cov.size(); ++i) img.data[i] = cov[i] ? float(10 * (id[i] + 1)) : -5.0f;
  DilateStats st;
  dilate(img, cov, 2, &st);
  // Every guard texel (8-adjacent to a chart) touches exactly one chart, so it holds that chart's
  // constant exactly; counted independently here.
  size_t guard = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (cov[size_t(y) * w + x]) continue;
      int owner = -1;
      bool two = false;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= w || ny >= h || !cov[size_t(ny) * w + nx]) continue;
          const int k = id[size_t(ny) * w + nx];
          if (owner >= 0 && owner != k) two = true;
          owner = k;
        }
      if (owner < 0) continue;
      ++guard;
      ASSERT_FALSE(two) << "test atlas must have gutters ≥ 2";
      EXPECT_EQ(img.data[size_t(y) * w + x], float(10 * (owner + 1))) << x << "," << y;
    }
  EXPECT_EQ(st.guard, guard);
  size_t covered = 0;
  for (uint8_t c : cov) covered += c;
  EXPECT_EQ(st.covered, covered);
  EXPECT_EQ(st.filled, cov.size() - covered);
}

TEST(Dilate, RingsAreChebyshevDistanceAndValuesConvex) {
  // One covered texel in a corner: ring r is the texels at Chebyshev distance r.
  ImageF img(10, 7, 2);
  std::vector<uint8_t> cov(70, 0);
  cov[0] = 1;
  img.data[0] = 3.5f, img.data[1] = -1.25f;
  fill_garbage(img, cov, 5);
  DilateStats st;
  dilate(img, cov, 2, &st);
  EXPECT_EQ(kDilateRings, 8);
  EXPECT_EQ(st.rings, 8);  // the column x = 9 is ring 9: beyond the rings, set to 0
  EXPECT_EQ(st.guard, 3u);
  EXPECT_EQ(st.far, 7u);
  for (size_t i = 0; i < 70; ++i) {
    const bool beyond = i % 10 == 9;
    EXPECT_EQ(img.data[i * 2], beyond ? 0.0f : 3.5f) << i;
    EXPECT_EQ(img.data[i * 2 + 1], beyond ? 0.0f : -1.25f) << i;
  }

  // Convexity: every filled value lies within the covered values' range, per channel.
  const Planes p = synthetic(53, 31);
  ImageF a = p.iz;
  fill_garbage(a, p.coverage, 9);
  float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
  for (size_t i = 0; i < p.coverage.size(); ++i)
    if (p.coverage[i])
      for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], a.data[i * 3 + c]), hi[c] = std::max(hi[c], a.data[i * 3 + c]);
  dilate(a, p.coverage, 2);
  for (size_t i = 0; i < p.coverage.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      EXPECT_GE(a.data[i * 3 + c], lo[c] - 1e-5f);
      EXPECT_LE(a.data[i * 3 + c], hi[c] + 1e-5f);
    }
}

TEST(Dilate, EmptyAndFullCoverage) {
  ImageF img(5, 4, 3);
  std::vector<uint8_t> none(20, 0), all(20, 1);
  fill_garbage(img, none, 3);
  ImageF full = img;
  DilateStats st;
  dilate(img, none, 2, &st);
  for (float v : img.data) EXPECT_EQ(v, 0.0f);
  EXPECT_EQ(st.rings, 0);
  EXPECT_EQ(st.filled, 20u);
  const ImageF before = full;
  dilate(full, all, 2, &st);
  EXPECT_EQ(full.data, before.data);
  EXPECT_EQ(st.covered, 20u);
  EXPECT_EQ(st.filled, 0u);
  EXPECT_THROW(dilate(img, std::vector<uint8_t>(3, 1), 1), Error);
}

TEST(Dilate, ThreadCountDoesNotChangeTheResult) {
  const Planes p = synthetic(211, 157);  // rings longer than the parallel grain
  ImageF a = p.iz, b = p.iz;
  fill_garbage(a, p.coverage, 4);
  b = a;
  dilate(a, p.coverage, 1);
  dilate(b, p.coverage, 2);
  EXPECT_EQ(std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)), 0);
}

TEST(Dilate, AhdImageFilledTexelsAreValidAndGarbageFree) {
  BakerOptions bo;
  bo.width = 37;
  bo.height = 23;
  bo.area_samples = 3;
  const ShImage sh = bake_analytic_scene(bo);
  const FitOptions opt;
  const AhdImage fit = fit_image(sh, opt, 2);
  AhdImage a = fit, b = fit;
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> g(-1e6f, 1e6f);
  for (AhdImage* x : {&a, &b})
    for (size_t i = 0; i < x->size(); ++i)
      if (!x->coverage[i]) {
        for (int c = 0; c < 3; ++c) x->iz[i * 3 + c] = g(rng), x->d[i * 3 + c] = g(rng);
        const size_t nr = x->one_ratio ? 1 : 3;
        for (size_t c = 0; c < nr; ++c) x->ratio[i * nr + c] = g(rng);
      }
  DilateStats st;
  dilate_ahd(a, opt.dz_min, 2, &st);
  dilate_ahd(b, opt.dz_min, 1);
  EXPECT_GT(st.guard, 0u);
  EXPECT_GT(st.filled, 0u);
  for (size_t i = 0; i < a.size(); ++i) {
    const AhdFit f = a.texel(i);
    if (a.coverage[i]) {
      ASSERT_TRUE(same_fit_bits(f, fit.texel(i))) << "covered texels untouched";
      continue;
    }
    ASSERT_TRUE(same_fit_bits(f, b.texel(i))) << "garbage-independent";
    EXPECT_NEAR(f.d[0] * f.d[0] + f.d[1] * f.d[1] + f.d[2] * f.d[2], 1.0f, 1e-5f);
    EXPECT_GE(f.d[2], opt.dz_min - 1e-6);
    for (int c = 0; c < 3; ++c) {
      EXPECT_GE(f.iz[c], 0.0f);
      EXPECT_GE(f.ratio[c], 0.0f);
      EXPECT_LE(f.ratio[c], 1.0f);
      EXPECT_GE(fitted_ca(f, c), 0.0f);
      EXPECT_GE(fitted_cd(f, c), 0.0f);
      // Self-consistent: the lobe gives back I_z along the normal.
      EXPECT_NEAR(fitted_ca(f, c) + f.d[2] * fitted_cd(f, c), f.iz[c], 1e-4 * (f.iz[c] + 1e-6));
    }
  }
}

namespace {

// The rule of mips/dilate.h computed the plain way: ring by ring (each ring found from the one
// before), every value of a ring from the state before it, with the sum dilate() documents; after
// `max_rings` rings the texels not reached are set to 0 (*far counts them).
std::vector<float> ring_by_ring(int w, int h, int ch, const std::vector<uint8_t>& cov, std::vector<float> v,
                                int* rings, int max_rings = kDilateRings, size_t* far = nullptr) {
  const int dx[8] = {-1, 0, 1, -1, 1, -1, 0, 1}, dy[8] = {-1, -1, -1, 0, 0, 1, 1, 1};
  const double wt[8] = {1, 2, 1, 2, 2, 1, 2, 1};
  std::vector<uint8_t> filled(cov.begin(), cov.end());
  for (uint8_t& f : filled) f = f ? 1 : 0;
  *rings = 0;
  std::vector<size_t> ring;  // ring 1: the uncovered texels next to a covered one
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (filled[size_t(y) * w + x]) continue;
      for (int k = 0; k < 8; ++k) {
        const int nx = x + dx[k], ny = y + dy[k];
        if (nx >= 0 && ny >= 0 && nx < w && ny < h && filled[size_t(ny) * w + nx]) {
          ring.push_back(size_t(y) * w + x);
          break;
        }
      }
    }
  std::vector<uint8_t> queued(filled);
  for (size_t i : ring) queued[i] = 1;
  if (far) *far = 0;
  for (;;) {
    if (ring.empty()) return v;
    if (*rings == max_rings) {
      for (size_t i = 0; i < filled.size(); ++i)
        if (!filled[i]) {
          std::fill_n(&v[i * size_t(ch)], ch, 0.0f);
          if (far) ++*far;
        }
      return v;
    }
    ++*rings;
    std::vector<float> out(ring.size() * size_t(ch));
    for (size_t r = 0; r < ring.size(); ++r) {
      const int x = int(ring[r] % size_t(w)), y = int(ring[r] / size_t(w));
      std::vector<double> a(size_t(ch), 0.0);
      double ws = 0;
      for (int k = 0; k < 8; ++k) {
        const int nx = x + dx[k], ny = y + dy[k];
        if (nx < 0 || ny < 0 || nx >= w || ny >= h || filled[size_t(ny) * w + nx] != 1) continue;
        for (int c = 0; c < ch; ++c) a[size_t(c)] += wt[k] * double(v[(size_t(ny) * w + nx) * ch + c]);
        ws += wt[k];
      }
      for (int c = 0; c < ch; ++c) out[r * ch + c] = float(a[size_t(c)] / ws);
    }
    std::vector<size_t> next;  // ring r + 1: the texels next to ring r not in a ring yet
    for (size_t r = 0; r < ring.size(); ++r) {
      std::copy_n(&out[r * ch], ch, &v[ring[r] * ch]);
      filled[ring[r]] = 1;
      const int x = int(ring[r] % size_t(w)), y = int(ring[r] / size_t(w));
      for (int k = 0; k < 8; ++k) {
        const int nx = x + dx[k], ny = y + dy[k];
        if (nx < 0 || ny < 0 || nx >= w || ny >= h || queued[size_t(ny) * w + nx]) continue;
        queued[size_t(ny) * w + nx] = 1;
        next.push_back(size_t(ny) * w + nx);
      }
    }
    ring.swap(next);
  }
}

// A wide gutter (hundreds of rings, the first ones longer than dilate's parallel chunks) around a
// few charts and lone texels, image edges included, garbage with NaN and infinities outside.
std::vector<uint8_t> sparse_coverage(int w, int h) {
  std::vector<uint8_t> cov(size_t(w) * h, 0);
  std::mt19937 rng(11);
  for (int k = 0; k < 40; ++k) {  // lone texels and small charts, some on an edge
    const int x0 = int(rng() % uint32_t(w)), y0 = int(rng() % uint32_t(h)), s = int(rng() % 5);
    for (int y = y0; y < std::min(h, y0 + s + 1); ++y)
      for (int x = x0; x < std::min(w, x0 + 2 * s + 1); ++x) cov[size_t(y) * w + x] = uint8_t(1 + rng() % 200);
  }
  for (int y = 0; y < h; ++y) cov[size_t(y) * w] = y < 3;  // a corner
  return cov;
}

void nasty_garbage(std::vector<float>& v, int ch, const std::vector<uint8_t>& cov) {
  const float bad[4] = {std::nanf(""), INFINITY, -INFINITY, -1e30f};
  for (size_t i = 0; i < cov.size(); ++i)
    if (!cov[i])
      for (int c = 0; c < ch; ++c) v[i * ch + c] = bad[(i + size_t(c)) % 4];
}

}  // namespace

// The distance-transform schedule of dilate() must give the ring-by-ring rule's bits exactly, for
// the channel counts it specialises (1, 3; 7 and 9 as dilate_ahd uses), more than 16, any threads.
TEST(Dilate, DistanceOrderGivesTheRingByRingBits) {
  const int w = 523, h = 347;  // odd sizes: rows of the rings are not aligned to anything
  const std::vector<uint8_t> cov = sparse_coverage(w, h);
  for (int ch : {1, 3, 7, 9, 20}) {
    std::vector<float> v(cov.size() * size_t(ch));
    for (size_t i = 0; i < v.size(); ++i) v[i] = float(std::sin(0.37 * double(i)) * 3.0 + 0.01 * double(i % 97));
    nasty_garbage(v, ch, cov);
    int rings = 0, all_rings = 0;
    size_t far = 0;
    const std::vector<float> want = ring_by_ring(w, h, ch, cov, v, &rings, kDilateRings, &far);
    ring_by_ring(w, h, ch, cov, v, &all_rings, 1 << 30);
    ASSERT_GT(all_rings, 40);  // the rings stop well before the gutters end
    ASSERT_EQ(rings, kDilateRings);
    ASSERT_GT(far, cov.size() / 4);
    for (int threads : {1, 2}) {
      ImageF img(w, h, ch);
      img.data = v;
      DilateStats st;
      dilate(img, cov, threads, &st);
      EXPECT_EQ(st.rings, rings) << ch;
      EXPECT_EQ(st.far, far) << ch;
      ASSERT_EQ(std::memcmp(img.data.data(), want.data(), want.size() * sizeof(float)), 0)
          << ch << " channels, " << threads << " threads";
    }
  }
}

// dilate_ambient (an L0 level's gutters, in its SH slots) against the same rule over the I_z plane.
TEST(Dilate, AmbientGivesTheRingByRingBits) {
  const int w = 401, h = 333;
  ShImage sh = make_sh_image(w, h, 1);
  sh.coverage = sparse_coverage(w, h);
  for (size_t i = 0; i < sh.data.size(); ++i) sh.data[i] = float(0.5 + 0.4 * std::sin(0.11 * double(i)));
  sh.data[7] = -0.5f;  // negative SH: I_z 0
  nasty_garbage(sh.data, 3, sh.coverage);
  std::vector<float> iz(sh.data.size());
  for (size_t i = 0; i < sh.texels(); ++i) ambient_level_iz(sh, i, &iz[i * 3]);
  int rings = 0;
  const std::vector<float> want = ring_by_ring(w, h, 3, sh.coverage, iz, &rings);
  for (int threads : {1, 2}) {
    ShImage a = sh;
    DilateStats st;
    dilate_ambient(a, threads, &st);
    EXPECT_EQ(st.rings, rings);
    for (size_t i = 0; i < a.texels(); ++i) {
      const float* got = a.coverage[i] ? sh.texel(i) : &want[i * 3];
      ASSERT_EQ(std::memcmp(a.texel(i), got, 3 * sizeof(float)), 0) << i << " " << threads;
    }
  }
}

TEST(Dilate, CoveragePlaneIsR8) {
  const std::vector<uint8_t> cov = {1, 0, 7, 0, 0, 1};
  const Image8 p = coverage_plane(3, 2, cov);
  EXPECT_EQ(p.channels, 1);
  EXPECT_EQ(p.data, (std::vector<uint8_t>{255, 0, 255, 0, 0, 255}));
  EXPECT_THROW(coverage_plane(2, 2, cov), Error);
}

// Why the rings may stop at kDilateRings (dilate.h): every 4×4 block a sampler can touch — one
// holding a covered or ring-1 texel — is encoded to the same bytes as with rings to the image's
// edge, and the blocks beyond are constant. BC6H (the I_z plane) on a wide gutter, sizes not a
// multiple of 4.
TEST(Dilate, SampledBlocksEncodeAsWithRingsToTheEdge) {
  const int w = 523, h = 347;
  const std::vector<uint8_t> cov = sparse_coverage(w, h);
  std::vector<float> v(cov.size() * 3);
  for (size_t i = 0; i < v.size(); ++i) v[i] = float(1.5 + std::sin(0.37 * double(i)) + 0.01 * double(i % 97));
  nasty_garbage(v, 3, cov);
  int rings = 0;
  ImageF all(w, h, 3), capped(w, h, 3);
  all.data = ring_by_ring(w, h, 3, cov, v, &rings, 1 << 30);
  ASSERT_GT(rings, 40);
  capped.data = v;
  dilate(capped, cov, 2);
  // Chebyshev distance ≤ 1 from the coverage, found directly.
  auto sampled = [&](int x, int y) {
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int nx = x + dx, ny = y + dy;
        if (nx >= 0 && ny >= 0 && nx < w && ny < h && cov[size_t(ny) * w + nx]) return true;
      }
    return false;
  };
  Bc6hOptions o;
  const std::vector<uint8_t> a = bc6h_encode_image(all, o), b = bc6h_encode_image(capped, o);
  const int bw = (w + 3) / 4, bh = (h + 3) / 4;
  int touched = 0, untouched = 0;
  for (int by = 0; by < bh; ++by)
    for (int bx = 0; bx < bw; ++bx) {
      bool s = false;
      for (int y = 4 * by; y < std::min(h, 4 * by + 4); ++y)
        for (int x = 4 * bx; x < std::min(w, 4 * bx + 4); ++x) s = s || sampled(x, y);
      const size_t at = (size_t(by) * bw + bx) * 16;
      if (s) {
        ++touched;
        ASSERT_EQ(std::memcmp(&a[at], &b[at], 16), 0) << "block " << bx << "," << by;
      } else {
        ++untouched;
      }
    }
  EXPECT_GT(touched, 100);
  EXPECT_GT(untouched, touched);  // most of the image is gutter beyond the rings
}
