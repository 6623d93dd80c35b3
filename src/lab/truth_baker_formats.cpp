#include "lab/truth_baker_formats.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "codecs/bc1.h"
#include "codecs/bc6h/bc6h_codec.h"
#include "sh/sh.h"

namespace ahd {

namespace {

constexpr double kLuma[3] = {0.2126, 0.7152, 0.0722};

// E_c(n) = e0_c + e_c · n for every texel: the L1 part of the SH's irradiance.
struct LinearIrradiance {
  std::vector<float> e0;  // texels × 3
  std::vector<float> e;   // texels × 3 channels × 3 axes (x, y, z)
};

// The SH truncated to its first 4 coefficients (not the L2 polynomial without its quadratic part:
// Y20 = c·(3z² − 1) also moves the constant e0).
LinearIrradiance linear_part(const ShImage& sh) {
  const size_t n = sh.texels();
  ShImage l1 = make_sh_image(sh.width, sh.height, 4);
  l1.coverage = sh.coverage;
  l1.normals = sh.normals;
  for (size_t i = 0; i < n; ++i) std::copy_n(sh.texel(i), 12, l1.texel(i));
  LinearIrradiance out;
  out.e0.resize(n * 3);
  out.e.resize(n * 9);
  for (size_t i = 0; i < n; ++i) {
    IrradiancePoly p[3];
    local_polys(l1, i, p);
    for (int c = 0; c < 3; ++c) {
      out.e0[i * 3 + c] = float(p[c].e0);
      for (int a = 0; a < 3; ++a) out.e[i * 9 + c * 3 + a] = float(p[c].e[a]);
    }
  }
  return out;
}

// The image through BC6H (unsigned, default quality) and back.
ImageF through_bc6h(ImageF img) {
  Bc6hOptions opt;
  const std::vector<uint8_t> blocks = bc6h_encode_image(img, opt);
  return bc6h_decode_image(blocks.data(), img.width, img.height, false);
}

float to_unorm8(float t) { return std::round(std::clamp(t, 0.0f, 1.0f) * 255.0f) / 255.0f; }

// Shared data and the decode E_c(n) = max(0, l0_c · (1 + k · (2t − 1) · n)) of both formats, where
// t holds per texel 3 axes (MonoSH: one vector) or 3 channels × 3 axes (Godot).
struct TFormat {
  std::vector<float> l0, t;
  bool per_channel = false;
  double k = 0;
};

TruthEval t_format_eval(std::shared_ptr<const TFormat> f) {
  return [f](size_t i, const double n[3], double out[3]) {
    for (int c = 0; c < 3; ++c) {
      const float* t = &f->t[f->per_channel ? i * 9 + size_t(c) * 3 : i * 3];
      double dot = 0;
      for (int a = 0; a < 3; ++a) dot += (2.0 * t[a] - 1.0) * n[a];
      out[c] = std::max(0.0, f->l0[i * 3 + size_t(c)] * (1.0 + f->k * dot));
    }
  };
}

ImageF image_of(const std::vector<float>& v, int w, int h, size_t stride, size_t offset) {
  ImageF img(w, h, 3);
  for (size_t i = 0; i < img.texels(); ++i)
    for (int c = 0; c < 3; ++c) img.data[i * 3 + size_t(c)] = v[i * stride + offset + size_t(c)];
  return img;
}

// Texels without coverage take the mean of their covered 8-neighbours, pass after pass (as a
// baker dilates its charts into the gutters before compressing); what no chart reaches gets `fill`.
void dilate(ImageF& img, std::vector<uint8_t> covered, float fill) {
  const int w = img.width, h = img.height, ch = img.channels;
  for (bool grew = true; grew;) {
    grew = false;
    std::vector<uint8_t> next = covered;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        if (covered[size_t(y) * size_t(w) + size_t(x)]) continue;
        std::vector<double> sum(size_t(ch), 0.0);
        int count = 0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if (nx < 0 || ny < 0 || nx >= w || ny >= h || !covered[size_t(ny) * size_t(w) + size_t(nx)]) continue;
            for (int c = 0; c < ch; ++c) sum[size_t(c)] += img.at(nx, ny)[c];
            ++count;
          }
        if (count == 0) continue;
        for (int c = 0; c < ch; ++c) img.at(x, y)[c] = float(sum[size_t(c)] / count);
        next[size_t(y) * size_t(w) + size_t(x)] = 1;
        grew = true;
      }
    covered = std::move(next);
  }
  for (size_t i = 0; i < img.texels(); ++i)
    if (!covered[i])
      for (int c = 0; c < ch; ++c) img.data[i * size_t(ch) + size_t(c)] = fill;
}

// Samples `lo` (the texture at 1/scale of w×h) bilinearly at the w×h texel centres, clamp to edge:
// what the GPU returns when the shader samples the smaller texture with the lightmap's UV.
ImageF upsample_bilinear(const ImageF& lo, int w, int h) {
  ImageF out(w, h, lo.channels);
  auto coord = [](int x, int full, int small, int& i0, int& i1, float& f) {
    const double u = (x + 0.5) * double(small) / double(full) - 0.5;
    const double fl = std::floor(u);
    f = float(u - fl);
    i0 = std::clamp(int(fl), 0, small - 1);
    i1 = std::clamp(int(fl) + 1, 0, small - 1);
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      int x0, x1, y0, y1;
      float fx, fy;
      coord(x, w, lo.width, x0, x1, fx);
      coord(y, h, lo.height, y0, y1, fy);
      for (int c = 0; c < lo.channels; ++c)
        out.at(x, y)[c] = (1 - fy) * ((1 - fx) * lo.at(x0, y0)[c] + fx * lo.at(x1, y0)[c]) +
                          fy * ((1 - fx) * lo.at(x0, y1)[c] + fx * lo.at(x1, y1)[c]);
    }
  return out;
}

// The irradiance along the surface normal, max(0, I_z), of the full SH (a plain lightmap's value).
std::vector<float> normal_irradiance(const ShImage& sh) {
  std::vector<float> c(sh.texels() * 3);
  const double z[3] = {0, 0, 1};
  for (size_t i = 0; i < sh.texels(); ++i) {
    IrradiancePoly p[3];
    local_polys(sh, i, p);
    for (int ch = 0; ch < 3; ++ch) c[i * 3 + size_t(ch)] = float(std::max(0.0, eval_irradiance(p[ch], z)));
  }
  return c;
}

double luma(const float* rgb) { return kLuma[0] * rgb[0] + kLuma[1] * rgb[1] + kLuma[2] * rgb[2]; }

}  // namespace

BakerFormatEval mono_sh_format(const ShImage& sh, bool quantised) {
  const LinearIrradiance li = linear_part(sh);
  const size_t n = li.e0.size() / 3;
  auto f = std::make_shared<TFormat>();
  f->k = 2.0;  // (2t − 1)·2·L0 = L1 for t = L1/(4·L0) + 0.5
  f->l0 = li.e0;
  f->t.resize(n * 3);
  for (size_t i = 0; i < n; ++i) {
    double y0 = 0, y[3] = {0, 0, 0};
    for (int c = 0; c < 3; ++c) {
      y0 += kLuma[c] * li.e0[i * 3 + size_t(c)];
      for (int a = 0; a < 3; ++a) y[a] += kLuma[c] * li.e[i * 9 + size_t(c) * 3 + size_t(a)];
    }
    for (int a = 0; a < 3; ++a) {
      const float t = y0 > 0 ? float(y[a] / (4.0 * y0) + 0.5) : 0.5f;
      f->t[i * 3 + size_t(a)] = quantised ? to_unorm8(t) : t;
    }
  }
  if (quantised) f->l0 = through_bc6h(image_of(f->l0, sh.width, sh.height, 3, 0)).data;
  return {t_format_eval(f), quantised ? 1.0 + 4.0 : 0.0,
          quantised ? "MonoSH (Bakery): L0 BC6H + L1 RGBA8" : "MonoSH (Bakery), float"};
}

BakerFormatEval godot_l1_format(const ShImage& sh, bool quantised) {
  const LinearIrradiance li = linear_part(sh);
  const size_t n = li.e0.size() / 3;
  auto f = std::make_shared<TFormat>();
  f->k = 4.0;  // 8·(t − 0.5)·L0 = L1 for t = L1/(8·L0) + 0.5
  f->per_channel = true;
  f->l0 = li.e0;
  f->t.resize(n * 9);
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      const double l0 = li.e0[i * 3 + size_t(c)];
      for (int a = 0; a < 3; ++a) {
        const double l1 = li.e[i * 9 + size_t(c) * 3 + size_t(a)];
        f->t[i * 9 + size_t(c) * 3 + size_t(a)] = l0 > 0 ? std::clamp(float(l1 / (8.0 * l0) + 0.5), 0.0f, 1.0f) : 0.5f;
      }
    }
  if (quantised) {
    f->l0 = through_bc6h(image_of(f->l0, sh.width, sh.height, 3, 0)).data;
    // One layer per axis: its RGB are the three channels' t along that axis.
    for (int a = 0; a < 3; ++a) {
      ImageF layer(sh.width, sh.height, 3);
      for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) layer.data[i * 3 + size_t(c)] = f->t[i * 9 + size_t(c) * 3 + size_t(a)];
      const ImageF back = through_bc6h(layer);
      for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) f->t[i * 9 + size_t(c) * 3 + size_t(a)] = back.data[i * 3 + size_t(c)];
    }
  }
  return {t_format_eval(f), quantised ? 4.0 : 0.0,
          quantised ? "L1 SH as Godot stores it: 4 BC6H layers" : "L1 SH as Godot stores it, float"};
}

BakerFormatEval godot_ldr_format(const ShImage& sh, bool quantised, int dir_scale) {
  const LinearIrradiance li = linear_part(sh);
  const int w = sh.width, h = sh.height;
  const int lw = (w + dir_scale - 1) / dir_scale, lh = (h + dir_scale - 1) / dir_scale;
  // The direction texture as the baker writes it at its own resolution: over each texel's
  // footprint (dir_scale² lightmap texels, the covered ones), Y(L1) / (8·Y(L0)) + 0.5.
  ImageF dir(lw, lh, 3);
  std::vector<uint8_t> covered(size_t(lw) * size_t(lh), 0);
  for (int y = 0; y < lh; ++y)
    for (int x = 0; x < lw; ++x) {
      double y0 = 0, y1[3] = {0, 0, 0};
      for (int dy = 0; dy < dir_scale; ++dy)
        for (int dx = 0; dx < dir_scale; ++dx) {
          const int fx = x * dir_scale + dx, fy = y * dir_scale + dy;
          if (fx >= w || fy >= h) continue;
          const size_t i = size_t(fy) * size_t(w) + size_t(fx);
          if (!sh.coverage[i]) continue;
          y0 += luma(&li.e0[i * 3]);
          for (int a = 0; a < 3; ++a)
            for (int c = 0; c < 3; ++c) y1[a] += kLuma[c] * li.e[i * 9 + size_t(c) * 3 + size_t(a)];
        }
      if (y0 <= 0) continue;
      covered[size_t(y) * size_t(lw) + size_t(x)] = 1;
      for (int a = 0; a < 3; ++a) dir.at(x, y)[a] = std::clamp(float(y1[a] / (8.0 * y0) + 0.5), 0.0f, 1.0f);
    }
  dilate(dir, covered, 0.5f);
  if (quantised) {
    for (float& v : dir.data) v = to_unorm8(v);  // the PNG Godot saves
    const std::vector<uint8_t> blocks = bc1_encode_image(dir);
    dir = bc1_decode_image(blocks.data(), lw, lh);
  }
  const ImageF full = dir_scale == 1 ? dir : upsample_bilinear(dir, w, h);
  auto f = std::make_shared<TFormat>();
  f->k = 4.0;  // 8·(t − 0.5)·L0, Godot's packed-L1 decode
  f->l0 = quantised ? through_bc6h(image_of(li.e0, w, h, 3, 0)).data : li.e0;
  f->t = full.data;
  const std::string name = dir_scale == 1 ? "Godot LDR directional (PR #100790)"
                                           : "Godot LDR directional, direction at 1/" + std::to_string(dir_scale) +
                                                 " resolution (PR #108405)";
  return {t_format_eval(f), quantised ? 1.0 + 0.5 / double(dir_scale * dir_scale) : 0.0,
          name + (quantised ? ": L0 BC6H + direction BC1" : ", float")};
}

BakerFormatEval unity_directional_format(const ShImage& sh, bool quantised) {
  const LinearIrradiance li = linear_part(sh);
  const size_t n = sh.texels();
  struct Unity {
    std::vector<float> c, dir;  // texels × 3 (C), texels × 4 (rgb = v·0.5 + 0.5, w)
  };
  auto u = std::make_shared<Unity>();
  u->c = normal_irradiance(sh);
  u->dir.resize(n * 4);
  for (size_t i = 0; i < n; ++i) {
    const double y0 = luma(&li.e0[i * 3]);
    double v[3] = {0, 0, 0};
    if (y0 > 0)
      for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) v[a] += kLuma[c] * li.e[i * 9 + size_t(c) * 3 + size_t(a)] / y0;
    const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (len > 1)
      for (double& x : v) x /= len;
    for (int a = 0; a < 3; ++a) u->dir[i * 4 + size_t(a)] = float(v[a] * 0.5 + 0.5);
    u->dir[i * 4 + 3] = float(0.5 + 0.5 * v[2]);  // the half-Lambert at the baking normal (0, 0, 1)
  }
  if (quantised) {
    u->c = through_bc6h(image_of(u->c, sh.width, sh.height, 3, 0)).data;
    for (float& x : u->dir) x = to_unorm8(x);
  }
  TruthEval eval = [u](size_t i, const double n[3], double out[3]) {
    const float* d = &u->dir[i * 4];
    double half_lambert = 0.5;
    for (int a = 0; a < 3; ++a) half_lambert += n[a] * (d[a] - 0.5);
    const double scale = half_lambert / std::max(1e-4, double(d[3]));
    for (int c = 0; c < 3; ++c) out[c] = u->c[i * 3 + size_t(c)] * scale;
  };
  return {eval, quantised ? 2.0 : 0.0,
          quantised ? "Unity Directional = Enlighten directional irradiance: BC6H + RGBA8 (for BC7, favours it)"
                    : "Unity Directional = Enlighten directional irradiance, float"};
}

BakerFormatEval plain_bc6h_format(const ShImage& sh) {
  auto c = std::make_shared<std::vector<float>>(
      through_bc6h(image_of(normal_irradiance(sh), sh.width, sh.height, 3, 0)).data);
  TruthEval eval = [c](size_t i, const double*, double out[3]) {
    for (int ch = 0; ch < 3; ++ch) out[ch] = (*c)[i * 3 + size_t(ch)];
  };
  return {eval, 1.0, "plain lightmap (I_z only): BC6H"};
}

std::vector<BakerFormatEval> baker_formats(const ShImage& sh, bool quantised) {
  std::vector<BakerFormatEval> f;
  f.push_back(mono_sh_format(sh, quantised));
  f.push_back(godot_l1_format(sh, quantised));
  if (quantised) f.push_back(godot_ldr_format(sh, quantised, 1));  // float: MonoSH's above
  f.push_back(godot_ldr_format(sh, quantised, 2));
  f.push_back(unity_directional_format(sh, quantised));
  if (quantised) f.push_back(plain_bc6h_format(sh));  // float: `report truth`'s plain row
  return f;
}

}  // namespace ahd
