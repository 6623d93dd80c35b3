// Shared by the baker-layout tests: the analytic scene in world space (what a baker would store),
// its exact irradiance, the irradiance of a read-back ShImage, random directions, and the
// one-clear-error check.
#pragma once
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "core/error.h"
#include "core/image.h"
#include "bakers/baker_layout.h"
#include "image/image_io.h"
#include "sample/analytic_baker.h"
#include "sh/sh.h"
#include "sh/sh_image.h"

namespace layout_test {

using namespace ahd;

constexpr int N = 16;

// The analytic scene (L1, tangent space) with, per texel, its chart's world frame (rows t, b, n).
struct WorldScene {
  ShImage tangent;
  std::vector<std::array<double, 9>> frame;
  ImageF normals;
};

inline WorldScene world_scene() {
  BakerOptions bo;
  bo.width = bo.height = N;
  bo.coeffs = 4;
  bo.area_samples = 3;
  WorldScene w{bake_analytic_scene(bo), {}, ImageF(N, N, 3)};
  for (int y = 0; y < N; ++y)
    for (int x = 0; x < N; ++x) {
      // The baker's charts: floor (left half, n = +y, t = +x, b = −z), wall (right half, n = +z).
      const bool wall = x >= N / 2;
      const std::array<double, 9> f = wall ? std::array<double, 9>{1, 0, 0, 0, 1, 0, 0, 0, 1}
                                           : std::array<double, 9>{1, 0, 0, 0, 0, -1, 0, 1, 0};
      w.frame.push_back(f);
      for (int a = 0; a < 3; ++a) w.normals.at(x, y)[a] = float(f[6 + a]);
    }
  return w;
}

// World-space linear form (E/π = L0 + L1·n, L1 in x,y,z) of texel i, channel c.
inline void world_linear(const WorldScene& w, size_t i, int c, double* l0, double l1[3]) {
  const float* t = w.tangent.texel(i);
  *l0 = kY00 * t[c];
  const double local[3] = {t[3 * 3 + c], t[1 * 3 + c], t[2 * 3 + c]};  // (x, y, z) = coeffs 3, 1, 2
  const auto& f = w.frame[i];
  for (int a = 0; a < 3; ++a) l1[a] = (f[0 + a] * local[0] + f[3 + a] * local[1] + f[6 + a] * local[2]) * kY1 / 1.5;
}

// The same summed over the colours (the luminance Bakery's and our MonoSH-style tests use: dot(., 1)).
inline void world_linear_luma(const WorldScene& w, size_t i, double* l0, double l1[3]) {
  *l0 = 0, l1[0] = l1[1] = l1[2] = 0;
  for (int c = 0; c < 3; ++c) {
    double a, b[3];
    world_linear(w, i, c, &a, b);
    *l0 += a;
    for (int k = 0; k < 3; ++k) l1[k] += b[k];
  }
}

// E/π at world direction n of the source scene, texel i, channel c.
inline double source_e_over_pi(const WorldScene& w, size_t i, int c, const double n[3]) {
  double l0, l1[3];
  world_linear(w, i, c, &l0, l1);
  return l0 + l1[0] * n[0] + l1[1] * n[1] + l1[2] * n[2];
}

// E/π of the read-back SH for a world direction n (rotated into the texel's own frame).
inline double readback_e_over_pi(const ShImage& sh, size_t i, int c, const double n[3]) {
  IrradiancePoly p[3];
  local_polys(sh, i, p);
  double R[3][3];
  const double nn[3] = {sh.normals[i * 3], sh.normals[i * 3 + 1], sh.normals[i * 3 + 2]};
  frame_from_normal(nn, R);
  double l[3];
  for (int a = 0; a < 3; ++a) l[a] = R[a][0] * n[0] + R[a][1] * n[1] + R[a][2] * n[2];
  return eval_irradiance(p[c], l) / kPi;
}

// Random directions in the texel's upper hemisphere.
inline std::vector<std::array<double, 3>> directions(const WorldScene& w, size_t i, int count, std::mt19937& rng) {
  std::normal_distribution<double> g;
  std::vector<std::array<double, 3>> out;
  const double* nz = &w.frame[i][6];
  while (int(out.size()) < count) {
    double d[3] = {g(rng), g(rng), g(rng)};
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (double& v : d) v /= len;
    if (d[0] * nz[0] + d[1] * nz[1] + d[2] * nz[2] < 0) continue;
    out.push_back({d[0], d[1], d[2]});
  }
  return out;
}

// Godot ≥ 4.4 packed: one half EXR, 4 layers stacked vertically (L0, then t = L1/(8·L0) + 0.5
// for L1y, L1z, L1x), channels B, G, R.
inline void write_godot_packed(const WorldScene& w, const std::string& path) {
  ImageF img(N, 4 * N, 3);
  for (size_t i = 0; i < w.tangent.texels(); ++i) {
    const int x = int(i % N), y = int(i / N);
    for (int c = 0; c < 3; ++c) {
      double l0, l1[3];
      world_linear(w, i, c, &l0, l1);
      img.at(x, y)[c] = float(l0);
      const double yzx[3] = {l1[1], l1[2], l1[0]};  // layers 1..3: L1y, L1z, L1x
      for (int k = 0; k < 3; ++k)
        img.at(x, y + (k + 1) * N)[c] = l0 > 0 ? float(std::clamp(yzx[k] / (8 * l0) + 0.5, 0.0, 1.0)) : 0.5f;
    }
  }
  write_image(path, img, /*half=*/true, {"R", "G", "B"});  // OpenEXR stores them sorted: B, G, R
}

// Bakery SH: base_L0.hdr (RGBE) + base_L1x/_L1y/_L1z.tga, t = L1/(4·L0) + 0.5 in 8 bits.
inline void write_bakery_sh(const WorldScene& w, const std::string& base) {
  ImageF l0(N, N, 3), l1[3] = {ImageF(N, N, 3), ImageF(N, N, 3), ImageF(N, N, 3)};
  for (size_t i = 0; i < w.tangent.texels(); ++i)
    for (int c = 0; c < 3; ++c) {
      double a, b[3];
      world_linear(w, i, c, &a, b);
      l0.data[i * 3 + c] = float(a);
      for (int k = 0; k < 3; ++k) l1[k].data[i * 3 + c] = a > 0 ? float(std::clamp(b[k] / (4 * a) + 0.5, 0.0, 1.0)) : 0.5f;
    }
  write_image(base + "_L0.hdr", l0);
  write_image(base + "_L1x.tga", l1[0]);
  write_image(base + "_L1y.tga", l1[1]);
  write_image(base + "_L1z.tga", l1[2]);
}

// The canonical layer / part names of the exr-layers-* and exr-parts-* presets.
inline const char* const kLayerNames[9] = {"L0", "L1m1", "L10", "L1p1", "L2m2", "L2m1", "L20", "L2p1", "L2p2"};

// Coefficient k of `src` as an RGB image.
inline ImageF coefficient_image(const ShImage& src, int k) {
  ImageF img(src.width, src.height, 3);
  for (size_t i = 0; i < src.texels(); ++i)
    for (int c = 0; c < 3; ++c) img.data[i * 3 + size_t(c)] = src.texel(i)[k * 3 + c];
  return img;
}

// One float EXR, one layer per coefficient: channels L0.R, L0.G, L0.B, L1m1.R, …
inline void write_exr_layers(const std::string& path, const ShImage& src) {
  ImageF img(src.width, src.height, 3 * src.coeffs);
  std::vector<std::string> names;
  for (int k = 0; k < src.coeffs; ++k)
    for (const char* c : {"R", "G", "B"}) names.push_back(std::string(kLayerNames[k]) + "." + c);
  img.data = src.data;  // the ShImage layout is already (texel, coefficient, colour)
  write_image(path, img, /*half=*/false, names);
}

// One float multi-part EXR, one part per coefficient (named as the layers), channels R, G, B.
// ImageOutput::open(name, nsubimages, specs) declares every part up front, as OpenEXR requires.
inline void write_exr_parts(const std::string& path, const ShImage& src) {
  std::vector<OIIO::ImageSpec> specs;
  for (int k = 0; k < src.coeffs; ++k) {
    specs.emplace_back(src.width, src.height, 3, OIIO::TypeDesc::FLOAT);
    specs.back().attribute("oiio:subimagename", kLayerNames[k]);
  }
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out && out->open(path, int(specs.size()), specs.data())) << OIIO::geterror();
  for (int k = 0; k < src.coeffs; ++k) {
    if (k > 0) {
      ASSERT_TRUE(out->open(path, specs[size_t(k)], OIIO::ImageOutput::AppendSubimage)) << out->geterror();
    }
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, coefficient_image(src, k).data.data())) << out->geterror();
  }
  out->close();
}

// Seed 001: {base}_r/_g/_b.exr, half RGBA, the colour's radiance-SH L0, y, z, x in R, G, B, A.
inline void write_three_rgba(const WorldScene& w, const std::string& base) {
  const char* suffix[3] = {"_r.exr", "_g.exr", "_b.exr"};
  for (int c = 0; c < 3; ++c) {
    ImageF img(N, N, 4);
    for (size_t i = 0; i < w.tangent.texels(); ++i) {
      double l0, l1[3];
      world_linear(w, i, c, &l0, l1);
      const double sh[4] = {l0 / kY00, 1.5 * l1[1] / kY1, 1.5 * l1[2] / kY1, 1.5 * l1[0] / kY1};
      for (int k = 0; k < 4; ++k) img.data[i * 4 + size_t(k)] = float(sh[k]);
    }
    write_image(base + suffix[c], img, /*half=*/true);
  }
}

// Bakery MonoSH: L0 per colour (RGBE) and one L1 ratio per axis for all colours (8-bit TGA), the
// luminance ratio t = L1/(4·L0) + 0.5 with Bakery's runtime luminance dot(·, 1).
inline void write_bakery_monosh(const WorldScene& w, const std::string& base) {
  ImageF l0(N, N, 3), l1(N, N, 3);
  for (size_t i = 0; i < w.tangent.texels(); ++i) {
    double lum0, lum1[3];
    world_linear_luma(w, i, &lum0, lum1);
    for (int c = 0; c < 3; ++c) {
      double a, b[3];
      world_linear(w, i, c, &a, b);
      l0.data[i * 3 + size_t(c)] = float(a);
    }
    for (int axis = 0; axis < 3; ++axis)  // rgb = x, y, z
      l1.data[i * 3 + size_t(axis)] = lum0 > 0 ? float(std::clamp(lum1[axis] / (4 * lum0) + 0.5, 0.0, 1.0)) : 0.5f;
  }
  write_image(base + "_L0.hdr", l0);
  write_image(base + "_L1.tga", l1);
}

// Unity directional, encoded as Unity's comment describes it ("close to plain diffuse response
// lightmaps, but normalmapped"; the encoder itself is closed): dir = the luminance's L1/(2·L0) + 0.5,
// scaled into the 8-bit cube when longer (a hemisphere of light already has |L1| = L0); colour/w
// such that the value along the geometric normal is the source's E/π; w varies on the 8-bit grid.
inline void write_unity_directional(const WorldScene& w, const std::string& base) {
  ImageF light(N, N, 3), dir(N, N, 4);
  for (size_t i = 0; i < w.tangent.texels(); ++i) {
    double lum0, lum1[3], half_dir[3];
    world_linear_luma(w, i, &lum0, lum1);
    const double longest = std::max({std::fabs(lum1[0]), std::fabs(lum1[1]), std::fabs(lum1[2])});
    for (int a = 0; a < 3; ++a) {
      dir.data[i * 4 + size_t(a)] = float(std::round((0.5 + 0.5 * lum1[a] / std::max(longest, lum0)) * 255) / 255);
      half_dir[a] = dir.data[i * 4 + size_t(a)] - 0.5;
    }
    const float wq = float(77 + (i * 37) % 178) / 255.0f;
    dir.data[i * 4 + 3] = wq;
    const double half_lambert = (w.frame[i][6] * half_dir[0] + w.frame[i][7] * half_dir[1] + w.frame[i][8] * half_dir[2]) + 0.5;
    for (int c = 0; c < 3; ++c)
      light.data[i * 3 + size_t(c)] = float(source_e_over_pi(w, i, c, &w.frame[i][6]) / half_lambert * wq);
  }
  write_image(base + "_comp_light.exr", light, /*half=*/true);
  write_image(base + "_comp_dir.png", dir);
}

// A fresh temp folder holding the world scene and its normal map, removed at the end; the test
// writes a baker's files for base() and read()s them back through a preset.
struct WorldBake {
  std::filesystem::path dir;
  WorldScene w = world_scene();
  std::string normals;

  explicit WorldBake(const std::string& tag) : dir(ahd_test::temp_dir(tag)), normals((dir / "n.exr").string()) {
    write_image(normals, w.normals);
  }
  ~WorldBake() { std::filesystem::remove_all(dir); }
  std::string base() const { return (dir / "lm").string(); }
  std::string file(const std::string& suffix) const { return base() + suffix; }
  ShImage read(const std::string& preset) const { return read_layout(load_layout(preset), base(), normals); }
};

// `fn` must throw one ahd::Error of a single line containing `needle`.
template <class Fn>
void expect_error(Fn fn, const std::string& needle) {
  try {
    fn();
    ADD_FAILURE() << "accepted; expected: " << needle;
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(needle), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

}  // namespace layout_test
