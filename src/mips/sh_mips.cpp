#include <algorithm>
#include <cmath>
#include <type_traits>

#include "core/error.h"
#include "core/large_buffer.h"
#include "core/parallel.h"
#include "mips/mips.h"
#include "sh/sh.h"

namespace ahd {
namespace {

// Radiance-SH coefficients (count 4 or 9, written at stride `stride`) whose irradiance polynomial
// equals p ON THE UNIT SPHERE: the inverse of irradiance_poly. On the sphere n·n = 1, so the trace
// of Q belongs to the constant; the traceless rest is band 2:
//   a(2z²−x²−y²) + b(x²−y²) + off-diagonal terms, with Y20 ∝ 3z²−1 = 2z²−x²−y² there.
void sh_from_poly(const IrradiancePoly& p, int count, double* out, int stride) {
  const double tr = p.q[0][0] + p.q[1][1] + p.q[2][2];
  const double e0 = p.e0 + tr / 3.0;
  out[0 * stride] = e0 / (kA0 * kY00);
  if (count < 4) return;
  out[1 * stride] = p.e[1] / (kA1 * kY1);
  out[2 * stride] = p.e[2] / (kA1 * kY1);
  out[3 * stride] = p.e[0] / (kA1 * kY1);
  if (count < 9) return;
  const double k = kA2;
  const double t00 = p.q[0][0] - tr / 3.0, t11 = p.q[1][1] - tr / 3.0, t22 = p.q[2][2] - tr / 3.0;
  out[4 * stride] = 2.0 * p.q[0][1] / (k * kY2a);
  out[5 * stride] = 2.0 * p.q[1][2] / (k * kY2a);
  out[6 * stride] = (t22 / 2.0) / (k * kY20);
  out[7 * stride] = 2.0 * p.q[0][2] / (k * kY2a);
  out[8 * stride] = ((t00 - t11) / 2.0) / (k * kY22);
}

constexpr int kMaxVals = kShCoeffsL2 * 3;

// Texel i's SH in its local frame (z = normal), in double: as stored for tangent-space images,
// rotated via the irradiance polynomial (exact for band-limited L1/L2) for world-space ones.
void local_coeffs(const ShImage& img, size_t i, double out[kMaxVals]) {
  const int nv = img.coeffs * 3;
  const float* nf = img.normals.empty() ? nullptr : &img.normals[i * 3];
  if (!nf || (nf[0] == 0.0f && nf[1] == 0.0f && nf[2] == 1.0f)) {  // identity frame: no round trip
    const float* t = img.texel(i);
    for (int v = 0; v < nv; ++v) out[v] = t[v];
    return;
  }
  IrradiancePoly p[3];
  local_polys(img, i, p);
  for (int c = 0; c < 3; ++c) sh_from_poly(p[c], img.coeffs, out + c, 3);
}

void check_image(const ShImage& img) {
  if (img.width <= 0 || img.height <= 0) throw Error("SH mips: image size must be positive");
  if (!valid_sh_coeffs(img.coeffs)) throw Error("SH mips: 1, 4 or 9 coefficients");
  if (img.data.size() != img.texels() * size_t(img.coeffs) * 3 || img.coverage.size() != img.texels() ||
      (!img.normals.empty() && img.normals.size() != img.texels() * 3))
    throw Error("SH mips: malformed SH image (data, coverage or normals size)");
}

}  // namespace

int mip_level_count(int width, int height) {
  int n = std::max(width, height), levels = 1;
  while (n > 1) n >>= 1, ++levels;
  return levels;
}

int chain_level_count(int width, int height, int max_levels) {
  if (max_levels < 0) throw Error("SH mips: max_levels must be ≥ 0");
  const int full = mip_level_count(width, height);
  return max_levels == 0 ? full : std::min(full, max_levels);
}

int mip_size(int n0, int level) { return std::max(1, n0 >> level); }

int mip_taps(int n_src, int i, MipTap taps[3]) {
  if (n_src <= 1) {
    taps[0] = {0, 1.0};
    return 1;
  }
  if (n_src % 2 == 0) {
    taps[0] = {2 * i, 0.5};
    taps[1] = {2 * i + 1, 0.5};
    return 2;
  }
  // n = 2m+1 → m coarse texels, each the box [i·n/m, (i+1)·n/m) in source texel units: it covers
  // texel 2i by (m−i)/m, 2i+1 fully and 2i+2 by (i+1)/m; normalised by the width n/m.
  const int m = n_src / 2;
  const double inv = 1.0 / double(n_src);
  taps[0] = {2 * i, double(m - i) * inv};
  taps[1] = {2 * i + 1, double(m) * inv};
  taps[2] = {2 * i + 2, double(i + 1) * inv};
  return 3;
}

ShImage downsample_sh(const ShImage& src, int threads, NormalRule rule) {
  check_image(src);
  const int W = std::max(1, src.width / 2), H = std::max(1, src.height / 2);
  const bool world = !src.normals.empty();
  const bool keep_world = world && rule == NormalRule::AverageThenRotate;
  ShImage dst;
  dst.width = W;
  dst.height = H;
  dst.coeffs = src.coeffs;
  assign_large(dst.data, size_t(W) * H * src.coeffs * 3, 0.0f);
  assign_large(dst.coverage, size_t(W) * H, uint8_t(0));
  if (keep_world) dst.normals.assign(size_t(W) * H * 3, 0.0f);
  if (world && !keep_world) {
    // Local-frame SH, flagged as "world space with normal +z": the identity frame (see NormalRule).
    dst.normals.assign(size_t(W) * H * 3, 0.0f);
    for (size_t i = 0; i < size_t(W) * H; ++i) dst.normals[i * 3 + 2] = 1.0f;
  }
  const int nv = src.coeffs * 3;

  // Taps of every column once; the rows in parallel (a call per row, not per texel).
  std::vector<MipTap> col_taps(size_t(W) * 3);
  std::vector<int> col_count(static_cast<size_t>(W));
  for (int X = 0; X < W; ++X) col_count[size_t(X)] = mip_taps(src.width, X, &col_taps[size_t(X) * 3]);
  if (!world) {
    // Tangent-space SH (no normals): the same sums in the same order, with the coefficient count
    // known at compile time (3, 12 or 27 values a texel).
    auto rows = [&](auto nv_constant) {
      constexpr int NV = decltype(nv_constant)::value;
      parallel_for(size_t(H), threads, 1, [&](size_t row) {
        MipTap ty[3];
        const int ny = mip_taps(src.height, int(row), ty);
        for (int X = 0; X < W; ++X) {
          const MipTap* tx = &col_taps[size_t(X) * 3];
          const int nx = col_count[size_t(X)];
          double acc[NV] = {}, wsum = 0;
          for (int b = 0; b < ny; ++b)
            for (int a = 0; a < nx; ++a) {
              const size_t i = size_t(ty[b].index) * src.width + tx[a].index;
              if (!src.coverage[i]) continue;
              const double wgt = tx[a].weight * ty[b].weight;
              const float* t = src.texel(i);
              for (int k = 0; k < NV; ++k) acc[k] += wgt * double(t[k]);
              wsum += wgt;
            }
          if (wsum <= 0) continue;  // uncovered: zero SH, dilation fills the fitted planes later
          const size_t o = row * size_t(W) + size_t(X);
          dst.coverage[o] = 1;
          float* out = dst.texel(o);
          for (int k = 0; k < NV; ++k) out[k] = float(acc[k] / wsum);
        }
      });
    };
    if (nv == 3) rows(std::integral_constant<int, 3>{});
    else if (nv == 12) rows(std::integral_constant<int, 12>{});
    else rows(std::integral_constant<int, 27>{});
    return dst;
  }
  parallel_for(size_t(H), threads, 1, [&](size_t row) {
    const int Y = int(row);
    MipTap ty[3];
    const int ny = mip_taps(src.height, Y, ty);
    for (int X = 0; X < W; ++X) {
      const size_t o = size_t(Y) * size_t(W) + size_t(X);
      const MipTap* tx = &col_taps[size_t(X) * 3];
      const int nx = col_count[size_t(X)];
      double acc[kMaxVals] = {}, nrm[3] = {}, wsum = 0;
      const float* first_normal = nullptr;
      for (int b = 0; b < ny; ++b)
        for (int a = 0; a < nx; ++a) {
          const size_t i = size_t(ty[b].index) * src.width + tx[a].index;
          if (!src.coverage[i]) continue;
          const double wgt = tx[a].weight * ty[b].weight;
          double v[kMaxVals];
          if (keep_world) {
            const float* t = src.texel(i);
            for (int k = 0; k < nv; ++k) v[k] = t[k];
            const float* nn = &src.normals[i * 3];
            for (int c = 0; c < 3; ++c) nrm[c] += wgt * nn[c];
            if (!first_normal) first_normal = nn;
          } else {
            local_coeffs(src, i, v);
          }
          for (int k = 0; k < nv; ++k) acc[k] += wgt * v[k];
          wsum += wgt;
        }
      if (wsum <= 0) continue;  // uncovered: zero SH, dilation fills the fitted planes later
      dst.coverage[o] = 1;
      float* out = dst.texel(o);
      for (int k = 0; k < nv; ++k) out[k] = float(acc[k] / wsum);
      if (keep_world) {
        const double len = std::sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
        float* nd = &dst.normals[o * 3];
        for (int c = 0; c < 3; ++c) nd[c] = len > 1e-12 ? float(nrm[c] / len) : first_normal[c];
      }
    }
  });
  return dst;
}

std::vector<ShImage> build_sh_mips(const ShImage& level0, int max_levels, int threads, NormalRule rule) {
  check_image(level0);
  const int levels = chain_level_count(level0.width, level0.height, max_levels);
  std::vector<ShImage> chain;
  chain.reserve(size_t(levels));
  chain.push_back(level0);
  for (int l = 1; l < levels; ++l) chain.push_back(downsample_sh(chain.back(), threads, rule));
  return chain;
}

std::vector<FittedLevel> fit_mip_chain(ShImage&& level0, const FitOptions& opt, int max_levels, int threads,
                                       std::vector<FitStats>* stats, std::vector<DilateStats>* dilate_stats,
                                       NormalRule rule) {
  check_image(level0);
  const int levels = chain_level_count(level0.width, level0.height, max_levels);
  std::vector<FittedLevel> out;
  out.reserve(size_t(levels));
  if (stats) stats->clear();
  if (dilate_stats) dilate_stats->clear();
  // Level by level, each SH level filtered from the previous one (the same chain build_sh_mips
  // makes), without a second copy of level 0 or a separate list of SH levels.
  for (int l = 0; l < levels; ++l) {
    FitStats fs;
    DilateStats ds;
    out.push_back(fit_level(l == 0 ? std::move(level0) : downsample_sh(out.back().sh, threads, rule), opt, threads,
                            &fs, &ds));
    if (stats) stats->push_back(fs);
    if (dilate_stats) dilate_stats->push_back(ds);
  }
  return out;
}

FittedLevel fit_level(ShImage&& sh, const FitOptions& opt, int threads, FitStats* stats, DilateStats* dilate_stats) {
  check_image(sh);
  // Uncovered texels are not fitted: dilation replaces them from the covered ones alone.
  AhdImage a = fit_image(sh, opt, threads, stats, /*skip_uncovered=*/true);
  dilate_ahd(a, opt.dz_min, threads, dilate_stats);
  return {std::move(sh), std::move(a)};
}

FittedLevel fit_ambient_level(ShImage&& sh, const FitOptions& opt, int threads, FitStats* stats,
                              DilateStats* dilate_stats) {
  check_image(sh);
  if (sh.coeffs != 1) throw Error("fit_ambient_level: needs an L0 image (1 coefficient)");
  if (stats) *stats = ambient_fit_stats(sh, opt, threads);
  dilate_ambient(sh, threads, dilate_stats);
  return {std::move(sh), AhdImage()};
}

std::vector<FittedLevel> fit_mip_chain(const ShImage& level0, const FitOptions& opt, int max_levels, int threads,
                                       std::vector<FitStats>* stats, std::vector<DilateStats>* dilate_stats,
                                       NormalRule rule) {
  return fit_mip_chain(ShImage(level0), opt, max_levels, threads, stats, dilate_stats, rule);
}

}  // namespace ahd
