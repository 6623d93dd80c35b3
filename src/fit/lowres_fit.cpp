#include "fit/lowres_fit.h"

#include <algorithm>
#include <cmath>

#include "core/parallel.h"
#include "fit/ahd_decode.h"
#include "fit/direction_refine.h"

namespace ahd {

BilinearTap bilinear_tap(int full, int low, int x) {
  const double t = (double(x) + 0.5) * double(low) / double(full) - 0.5;
  const double f = std::floor(t);
  BilinearTap tap;
  tap.w1 = t - f;
  tap.x0 = std::clamp(int(f), 0, low - 1);
  tap.x1 = std::clamp(int(f) + 1, 0, low - 1);
  return tap;
}

namespace {

std::vector<BilinearTap> taps_of(int full, int low) {
  std::vector<BilinearTap> t(static_cast<size_t>(full));
  for (int x = 0; x < full; ++x) t[size_t(x)] = bilinear_tap(full, low, x);
  return t;
}

// The full-res texels [lo[X], hi[X]) whose taps reach low-res texel X (taps are monotone in x).
void reach_of(const std::vector<BilinearTap>& taps, int low, std::vector<int>* lo, std::vector<int>* hi) {
  lo->assign(size_t(low), int(taps.size()));
  hi->assign(size_t(low), 0);
  for (int x = 0; x < int(taps.size()); ++x)
    for (int X : {taps[size_t(x)].x0, taps[size_t(x)].x1}) {
      (*lo)[size_t(X)] = std::min((*lo)[size_t(X)], x);
      (*hi)[size_t(X)] = std::max((*hi)[size_t(X)], x + 1);
    }
}

// The weight texel X gets in a tap (both taps may be X at an edge).
double weight_of(const BilinearTap& t, int X) {
  return (t.x0 == X ? 1.0 - t.w1 : 0.0) + (t.x1 == X ? t.w1 : 0.0);
}

// The full-res texels of low-res texel X's box: [first[X], first[X + 1]).
std::vector<int> box_starts(int full, int low) {
  std::vector<int> first(size_t(low) + 1, full);
  for (int x = full - 1; x >= 0; --x) first[size_t(box_owner(full, low, x))] = x;
  for (int X = low - 1; X >= 0; --X) first[size_t(X)] = std::min(first[size_t(X)], first[size_t(X) + 1]);
  return first;
}

}  // namespace

void bilinear_upsample(const float* src, int lw, int lh, int channels, int w, int h, float* dst) {
  const std::vector<BilinearTap> tx = taps_of(w, lw);
  const size_t row = size_t(lw) * size_t(channels);
  for (int y = 0; y < h; ++y) {
    const BilinearTap ty = bilinear_tap(h, lh, y);
    const float* r0 = src + size_t(ty.x0) * row;
    const float* r1 = src + size_t(ty.x1) * row;
    float* out = dst + size_t(y) * size_t(w) * size_t(channels);
    for (int x = 0; x < w; ++x) {
      const BilinearTap& t = tx[size_t(x)];
      for (int c = 0; c < channels; ++c) {
        const size_t a = size_t(t.x0) * size_t(channels) + size_t(c), b = size_t(t.x1) * size_t(channels) + size_t(c);
        const double top = (1.0 - t.w1) * r0[a] + t.w1 * r0[b];
        const double bottom = (1.0 - t.w1) * r1[a] + t.w1 * r1[b];
        out[size_t(x) * size_t(channels) + size_t(c)] = float((1.0 - ty.w1) * top + ty.w1 * bottom);
      }
    }
  }
}

LowResDirections lowres_directions(const ShImage& sh, int lw, int lh, const FitOptions& opt, int threads) {
  LowResDirections out;
  out.width = lw, out.height = lh;
  out.d.assign(size_t(lw) * size_t(lh) * 3, 0.0f);
  out.coverage.assign(size_t(lw) * size_t(lh), 0);
  const std::vector<int> bx = box_starts(sh.width, lw), by = box_starts(sh.height, lh);
  parallel_for(size_t(lw) * size_t(lh), threads, 16, [&](size_t k) {
    const int X = int(k % size_t(lw)), Y = int(k / size_t(lw));
    IrradiancePoly mean[3];
    int n = 0;
    for (int y = by[size_t(Y)]; y < by[size_t(Y) + 1]; ++y)
      for (int x = bx[size_t(X)]; x < bx[size_t(X) + 1]; ++x) {
        const size_t i = size_t(y) * size_t(sh.width) + size_t(x);
        if (!sh.coverage[i]) continue;
        IrradiancePoly p[3];
        local_polys(sh, i, p);
        for (int c = 0; c < 3; ++c) {
          mean[c].e0 += p[c].e0;
          for (int a = 0; a < 3; ++a) {
            mean[c].e[a] += p[c].e[a];
            for (int b = 0; b < 3; ++b) mean[c].q[a][b] += p[c].q[a][b];
          }
        }
        ++n;
      }
    float* d = &out.d[k * 3];
    d[2] = 1.0f;
    if (n == 0) return;
    for (int c = 0; c < 3; ++c) {
      mean[c].e0 /= n;
      for (int a = 0; a < 3; ++a) {
        mean[c].e[a] /= n;
        for (int b = 0; b < 3; ++b) mean[c].q[a][b] /= n;
      }
    }
    const AhdFit f = fit_texel(mean, opt);
    for (int a = 0; a < 3; ++a) d[a] = f.d[a];
    out.coverage[k] = 1;
  });
  return out;
}

RatioQuadratics ratio_quadratics(const ShImage& sh, const float* iz, const float* d, const FitOptions& opt,
                                 int threads) {
  RatioQuadratics q;
  q.width = sh.width, q.height = sh.height;
  q.channels = opt.ratio_form == RatioForm::Rgb ? 3 : 1;
  const size_t n = sh.texels() * size_t(q.channels);
  q.a.assign(n, 0.0);
  q.n.assign(n, 0.0);
  parallel_for(sh.texels(), threads, 1024, [&](size_t i) {
    if (!sh.coverage[i]) return;
    // As the decoder reads the texel: d normalised and put above the horizon.
    double u[3], ca[3], cd[3];
    const float ratio1[3] = {1, 1, 1};
    decode_colours(&iz[i * 3], &d[i * 3], ratio1, opt.dz_min, ca, cd, u);
    IrradiancePoly p[3];
    local_polys(sh, i, p);
    const LuneMoments m = lune_moments(p, u);
    // With C_a = r I, C_d = (1 − r) I k (k = 1/d_z) the error of channel c is I²·hh·r² − 2·num·r + …
    // (least_squares_ratio_k, direction_refine.cpp, is its minimiser summed over the channels).
    const double k = 1.0 / u[2];
    const double hh = 2.0 * kPi - 2.0 * k * m.g1 + k * k * m.g2;
    for (int c = 0; c < 3; ++c) {
      const double I = std::max(0.0f, iz[i * 3 + c]);
      if (!(I > 0.0)) continue;
      const double num = I * (I * (k * k * m.g2 - k * m.g1) + hemisphere_integral(p[c]) - k * m.f1[c]);
      const size_t s = i * size_t(q.channels) + size_t(q.channels == 3 ? c : 0);
      q.a[s] += I * I * hh;
      q.n[s] += num;
    }
  });
  return q;
}

std::vector<float> lowres_box_ratio(const RatioQuadratics& q, int lw, int lh) {
  const int ch = q.channels;
  std::vector<float> ratio(size_t(lw) * size_t(lh) * size_t(ch), 1.0f);
  std::vector<double> a(ratio.size(), 0.0), n(ratio.size(), 0.0);
  for (int y = 0; y < q.height; ++y) {
    const int Y = box_owner(q.height, lh, y);
    for (int x = 0; x < q.width; ++x) {
      const size_t k = (size_t(Y) * size_t(lw) + size_t(box_owner(q.width, lw, x))) * size_t(ch);
      const size_t i = (size_t(y) * size_t(q.width) + size_t(x)) * size_t(ch);
      for (int c = 0; c < ch; ++c) a[k + size_t(c)] += q.a[i + size_t(c)], n[k + size_t(c)] += q.n[i + size_t(c)];
    }
  }
  for (size_t k = 0; k < ratio.size(); ++k)
    if (a[k] > 0.0) ratio[k] = float(std::clamp(n[k] / a[k], 0.0, 1.0));
  return ratio;
}

void lowres_ratio_sweeps(const RatioQuadratics& q, int lw, int lh, std::vector<float>& ratio, int sweeps,
                         int threads) {
  const int w = q.width, h = q.height, ch = q.channels;
  const std::vector<BilinearTap> tx = taps_of(w, lw), ty = taps_of(h, lh);
  std::vector<int> xlo, xhi, ylo, yhi;
  reach_of(tx, lw, &xlo, &xhi);
  reach_of(ty, lh, &ylo, &yhi);
  // The decoded (sampled) ratio of every full-res texel, kept current as low-res texels change.
  std::vector<double> r(size_t(w) * size_t(h) * size_t(ch));
  auto sample = [&](int x, int y, int c) {
    const BilinearTap &a = tx[size_t(x)], &b = ty[size_t(y)];
    auto v = [&](int X, int Y) { return double(ratio[(size_t(Y) * size_t(lw) + size_t(X)) * size_t(ch) + size_t(c)]); };
    return (1.0 - b.w1) * ((1.0 - a.w1) * v(a.x0, b.x0) + a.w1 * v(a.x1, b.x0)) +
           b.w1 * ((1.0 - a.w1) * v(a.x0, b.x1) + a.w1 * v(a.x1, b.x1));
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < ch; ++c) r[(size_t(y) * size_t(w) + size_t(x)) * size_t(ch) + size_t(c)] = sample(x, y, c);
  for (int s = 0; s < sweeps; ++s)
    for (int parity = 0; parity < 4; ++parity) {
      const int px = parity & 1, py = parity >> 1;
      const int nx = (lw - px + 1) / 2, ny = (lh - py + 1) / 2;
      if (nx <= 0 || ny <= 0) continue;
      // Texels of one parity class share no full-res texel (a texel's taps are adjacent columns
      // and rows), so they update independently: the same bytes at any thread count.
      parallel_for(size_t(nx) * size_t(ny), threads, 4, [&](size_t j) {
        const int X = px + 2 * int(j % size_t(nx)), Y = py + 2 * int(j / size_t(nx));
        const size_t k = (size_t(Y) * size_t(lw) + size_t(X)) * size_t(ch);
        for (int c = 0; c < ch; ++c) {
          double g = 0, hdiag = 0;
          for (int y = ylo[size_t(Y)]; y < yhi[size_t(Y)]; ++y) {
            const double wy = weight_of(ty[size_t(y)], Y);
            if (wy == 0.0) continue;
            for (int x = xlo[size_t(X)]; x < xhi[size_t(X)]; ++x) {
              const double wt = wy * weight_of(tx[size_t(x)], X);
              const size_t i = (size_t(y) * size_t(w) + size_t(x)) * size_t(ch) + size_t(c);
              if (wt == 0.0 || q.a[i] == 0.0) continue;
              g += wt * (q.a[i] * r[i] - q.n[i]);
              hdiag += wt * wt * q.a[i];
            }
          }
          if (!(hdiag > 0.0)) continue;
          const double old = ratio[k + size_t(c)];
          const float now = float(std::clamp(old - g / hdiag, 0.0, 1.0));
          const double delta = double(now) - old;
          if (delta == 0.0) continue;
          ratio[k + size_t(c)] = now;
          for (int y = ylo[size_t(Y)]; y < yhi[size_t(Y)]; ++y) {
            const double wy = weight_of(ty[size_t(y)], Y);
            for (int x = xlo[size_t(X)]; x < xhi[size_t(X)]; ++x) {
              const double wt = wy * weight_of(tx[size_t(x)], X);
              if (wt != 0.0) r[(size_t(y) * size_t(w) + size_t(x)) * size_t(ch) + size_t(c)] += wt * delta;
            }
          }
        }
      });
    }
}

double lowres_ratio_objective(const RatioQuadratics& q, int lw, int lh, const std::vector<float>& ratio) {
  const int ch = q.channels;
  std::vector<float> r(size_t(q.width) * size_t(q.height) * size_t(ch));
  bilinear_upsample(ratio.data(), lw, lh, ch, q.width, q.height, r.data());
  double sum = 0;
  for (size_t i = 0; i < r.size(); ++i) sum += q.a[i] * double(r[i]) * r[i] - 2.0 * q.n[i] * r[i];
  return sum;
}

namespace {

// Hemi-octahedral uv in [0,1]² → unit direction, as the decoder reads a direction plane
// (pipeline/plane_decode.cpp unit_uv_to_dir: the same formula, here without the pipeline).
void uv_to_dir(double u01, double v01, double d[3]) {
  const double u = u01 * 2.0 - 1.0, v = v01 * 2.0 - 1.0;
  const double px = (u + v) * 0.5, py = (u - v) * 0.5;
  d[0] = px, d[1] = py, d[2] = std::max(0.0, 1.0 - std::abs(px) - std::abs(py));
  const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  for (int i = 0; i < 3; ++i) d[i] /= len;
}

}  // namespace

void lowres_direction_sweeps(const ShImage& sh, const float* iz, int lw, int lh, std::vector<float>& uv,
                             std::vector<float>& ratio, const FitOptions& opt, int sweeps, int threads) {
  const int w = sh.width, h = sh.height;
  const int ch = opt.ratio_form == RatioForm::Rgb ? 3 : 1;
  const std::vector<BilinearTap> tx = taps_of(w, lw), ty = taps_of(h, lh);
  std::vector<int> xlo, xhi, ylo, yhi;
  reach_of(tx, lw, &xlo, &xhi);
  reach_of(ty, lh, &ylo, &yhi);
  auto at = [&](const std::vector<float>& img, int n, int X, int Y, int c) {
    return double(img[(size_t(Y) * size_t(lw) + size_t(X)) * size_t(n) + size_t(c)]);
  };
  // Bilinear sample of img (n channels) at full-res (x, y), with texel (X, Y)'s own contribution
  // left out; *wk = that texel's weight.
  auto sample_without = [&](const std::vector<float>& img, int n, int x, int y, int X, int Y, int c, double* wk) {
    const BilinearTap &a = tx[size_t(x)], &b = ty[size_t(y)];
    double v = 0, own = 0;
    const int xs[2] = {a.x0, a.x1}, ys[2] = {b.x0, b.x1};
    const double wx[2] = {1.0 - a.w1, a.w1}, wy[2] = {1.0 - b.w1, b.w1};
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) {
        const double wt = wx[i] * wy[j];
        if (xs[i] == X && ys[j] == Y) own += wt;
        else v += wt * at(img, n, xs[i], ys[j], c);
      }
    *wk = own;
    return v;
  };
  struct Reached {
    IrradiancePoly p[3];
    double f0[3], I[3];
    double wk, uv_base[2], r_base[3];
  };
  double step = 1.0 / 32.0;
  for (int s = 0; s < sweeps; ++s, step *= 0.5)
    for (int parity = 0; parity < 4; ++parity) {
      const int px = parity & 1, py = parity >> 1;
      const int nx = (lw - px + 1) / 2, ny = (lh - py + 1) / 2;
      if (nx <= 0 || ny <= 0) continue;
      parallel_for(size_t(nx) * size_t(ny), threads, 1, [&](size_t j) {
        const int X = px + 2 * int(j % size_t(nx)), Y = py + 2 * int(j / size_t(nx));
        std::vector<Reached> reached;
        for (int y = ylo[size_t(Y)]; y < yhi[size_t(Y)]; ++y)
          for (int x = xlo[size_t(X)]; x < xhi[size_t(X)]; ++x) {
            const size_t i = size_t(y) * size_t(w) + size_t(x);
            if (!sh.coverage[i]) continue;
            Reached r;
            r.uv_base[0] = sample_without(uv, 2, x, y, X, Y, 0, &r.wk);
            r.uv_base[1] = sample_without(uv, 2, x, y, X, Y, 1, &r.wk);
            if (r.wk == 0.0) continue;
            for (int c = 0; c < ch; ++c) r.r_base[c] = sample_without(ratio, ch, x, y, X, Y, c, &r.wk);
            local_polys(sh, i, r.p);
            for (int c = 0; c < 3; ++c) {
              r.f0[c] = hemisphere_integral(r.p[c]);
              r.I[c] = std::max(0.0f, iz[i * 3 + size_t(c)]);
            }
            reached.push_back(r);
          }
        if (reached.empty()) return;
        // The summed error (up to a constant) of candidate uv (cu, cv), with this texel's ratio
        // re-solved (clamped to [0,1]) into rk.
        std::vector<double> a(reached.size() * size_t(ch)), n(reached.size() * size_t(ch));
        auto evaluate = [&](double cu, double cv, double rk[3]) {
          double A[3] = {0, 0, 0}, B[3] = {0, 0, 0}, sum = 0;
          std::fill(a.begin(), a.end(), 0.0);
          std::fill(n.begin(), n.end(), 0.0);
          for (size_t t = 0; t < reached.size(); ++t) {
            const Reached& r = reached[t];
            double d[3];
            uv_to_dir(r.uv_base[0] + r.wk * cu, r.uv_base[1] + r.wk * cv, d);
            tilt_above_horizon(d, opt.dz_min);
            const LuneMoments m = lune_moments(r.p, d);
            const double k = 1.0 / d[2];
            const double hh = 2.0 * kPi - 2.0 * k * m.g1 + k * k * m.g2;
            for (int c = 0; c < 3; ++c) {
              const double I = r.I[c];
              if (!(I > 0.0)) continue;
              const int q = ch == 3 ? c : 0;
              a[t * size_t(ch) + size_t(q)] += I * I * hh;
              n[t * size_t(ch) + size_t(q)] += I * (I * (k * k * m.g2 - k * m.g1) + r.f0[c] - k * m.f1[c]);
              sum += I * I * k * k * m.g2 - 2.0 * I * k * m.f1[c];  // the r-independent part
            }
            for (int q = 0; q < ch; ++q) {
              const double aq = a[t * size_t(ch) + size_t(q)], nq = n[t * size_t(ch) + size_t(q)];
              A[q] += aq * r.wk * r.wk;
              B[q] += r.wk * (nq - aq * r.r_base[q]);
            }
          }
          for (int q = 0; q < ch; ++q) rk[q] = A[q] > 0.0 ? std::clamp(B[q] / A[q], 0.0, 1.0) : at(ratio, ch, X, Y, q);
          for (size_t t = 0; t < reached.size(); ++t)
            for (int q = 0; q < ch; ++q) {
              const double r = reached[t].r_base[q] + reached[t].wk * rk[q];
              sum += a[t * size_t(ch) + size_t(q)] * r * r - 2.0 * n[t * size_t(ch) + size_t(q)] * r;
            }
          return sum;
        };
        const double u0 = at(uv, 2, X, Y, 0), v0 = at(uv, 2, X, Y, 1);
        double best_r[3], r_try[3];
        double best = evaluate(u0, v0, best_r), bu = u0, bv = v0;
        auto consider = [&](double cu, double cv) {
          cu = std::clamp(cu, 0.0, 1.0), cv = std::clamp(cv, 0.0, 1.0);
          if (cu == bu && cv == bv) return;
          const double e = evaluate(cu, cv, r_try);
          if (e < best) {
            best = e, bu = cu, bv = cv;
            for (int q = 0; q < ch; ++q) best_r[q] = r_try[q];
          }
        };
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int XX = X + dx, YY = Y + dy;
            if ((dx || dy) && XX >= 0 && YY >= 0 && XX < lw && YY < lh) consider(at(uv, 2, XX, YY, 0), at(uv, 2, XX, YY, 1));
          }
        const double cu = bu, cv = bv;  // the pattern around the best so far
        consider(cu + step, cv), consider(cu - step, cv), consider(cu, cv + step), consider(cu, cv - step);
        const size_t k = size_t(Y) * size_t(lw) + size_t(X);
        uv[k * 2] = float(bu), uv[k * 2 + 1] = float(bv);
        for (int q = 0; q < ch; ++q) ratio[k * size_t(ch) + size_t(q)] = float(best_r[q]);
      });
    }
}

}  // namespace ahd
