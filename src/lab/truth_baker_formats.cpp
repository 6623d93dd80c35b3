#include "lab/truth_baker_formats.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

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

std::vector<BakerFormatEval> baker_formats(const ShImage& sh, bool quantised) {
  std::vector<BakerFormatEval> f;
  f.push_back(mono_sh_format(sh, quantised));
  f.push_back(godot_l1_format(sh, quantised));
  return f;
}

}  // namespace ahd
