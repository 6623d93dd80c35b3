// `ahdpack decode` against the bakers' own runtime: the analytic scene stored in Godot's and
// Bakery's exact file formats, converted by the CLI, decoded by the CLI for random normals, and
// compared with the baker's shader formula (bakers.md) evaluated on the stored files.
//
// Along the surface normal the AHD model is exact (I_z kept), so the two agree to storage
// precision. Off the normal AHD is a model of the SH, not the SH: there the bound is the model's
// own error — the unquantised fit of the same read-back evaluated for the same normals — plus what
// quantising the planes may add. Both figures are printed.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

#include "layout_test_scene.h"
#include "pipeline/convert.h"

namespace fs = std::filesystem;
using namespace ahd;
using namespace layout_test;

namespace {

// The baker's runtime: E/π of texel i, colour c, for a WORLD direction n, from its stored files.
using Runtime = std::function<double(size_t i, int c, const double n[3])>;

struct Agreement {
  double along_normal = 0;  // max |decode − runtime| / runtime along the surface normal
  double decode_rms = 0;    // RMS(decode − runtime) / RMS(runtime), random normals
  double model_rms = 0;     // the same for the unquantised AHD fit (the model's own error)
};

// Random world directions in each texel's upper hemisphere, as tangent-space normals for
// `ahdpack decode --normals` (the frame of world-space conversions is frame_from_normal(n)).
Agreement decode_vs_runtime(const WorldBake& b, const std::string& layout, const Runtime& runtime) {
  const fs::path out = b.dir / "out";
  const auto conv = ahd_test::run_cli({"convert", b.base(), "--layout", layout, "--normals", b.normals, "-o",
                                       (out / "a.ktx2").string(), "--direction", "keep", "-q"});
  EXPECT_EQ(conv.exit_code, 0) << conv.output;
  const ShImage sh = b.read(layout);
  PipelineOptions opt;
  opt.measure = Measure::Off;
  PipelineResult fr;
  const std::vector<FittedLevel> fit = fit_levels(sh, opt, &fr);

  Agreement a;
  std::mt19937 rng(7);
  double err2 = 0, model2 = 0, ref2 = 0;
  for (int round = 0; round < 5; ++round) {
    // Round 0: the surface normal itself; then random directions.
    ImageF tangent_n(N, N, 3);
    std::vector<std::array<double, 3>> world_n(sh.texels());
    for (size_t i = 0; i < sh.texels(); ++i) {
      const double* nz = &b.w.frame[i][6];
      world_n[i] = round == 0 ? std::array<double, 3>{nz[0], nz[1], nz[2]} : directions(b.w, i, 1, rng)[0];
      double R[3][3];
      const double nn[3] = {sh.normals[i * 3], sh.normals[i * 3 + 1], sh.normals[i * 3 + 2]};
      frame_from_normal(nn, R);
      for (int r = 0; r < 3; ++r)
        tangent_n.at(int(i % N), int(i / N))[r] =
            float(R[r][0] * world_n[i][0] + R[r][1] * world_n[i][1] + R[r][2] * world_n[i][2]);
    }
    const std::string npath = (b.dir / "tn.exr").string(), epath = (b.dir / "e.exr").string();
    write_image(npath, tangent_n);
    const auto dec = ahd_test::run_cli({"decode", (out / "a.json").string(), "-o", epath, "--normals", npath});
    EXPECT_EQ(dec.exit_code, 0) << dec.output;
    const ImageF e = read_image(epath);
    for (size_t i = 0; i < sh.texels(); ++i) {
      if (!b.w.tangent.coverage[i]) continue;
      const float* tn = tangent_n.at(int(i % N), int(i / N));
      const AhdFit f = fit[0].ahd.texel(i);
      for (int c = 0; c < 3; ++c) {
        const double rt = runtime(i, c, world_n[i].data());
        const double dec_v = e.data[i * 3 + c] / kPi;
        const double dn = std::max(0.0, double(tn[0] * f.d[0] + tn[1] * f.d[1] + tn[2] * f.d[2]));
        const double model_v = (fitted_ca(f, c) + dn * fitted_cd(f, c)) / kPi;
        if (round == 0) a.along_normal = std::max(a.along_normal, std::fabs(dec_v - rt) / (std::fabs(rt) + 1e-6));
        else err2 += (dec_v - rt) * (dec_v - rt), model2 += (model_v - rt) * (model_v - rt), ref2 += rt * rt;
      }
    }
  }
  a.decode_rms = std::sqrt(err2 / ref2);
  a.model_rms = std::sqrt(model2 / ref2);
  std::printf("%s: decode vs runtime along the normal %.2e (max rel); random normals RMS %.3f (AHD model alone %.3f)\n",
              layout.c_str(), a.along_normal, a.decode_rms, a.model_rms);
  return a;
}

}  // namespace

TEST(DecodeVsRuntime, GodotPacked) {
  const WorldBake b("dvr_godot");
  write_godot_packed(b.w, b.file(".exr"));
  const ImageF s = read_image(b.file(".exr"));
  // Godot's forward_clustered shader: sh = L0 + L0·((t − 0.5)·2)·4·n per layer (y, z, x).
  const Runtime godot = [&](size_t i, int c, const double n[3]) {
    const int x = int(i % N), y = int(i / N);
    const double L0 = s.at(x, y)[c];
    return L0 + 8 * L0 * ((s.at(x, y + N)[c] - 0.5) * n[1] + (s.at(x, y + 2 * N)[c] - 0.5) * n[2] +
                          (s.at(x, y + 3 * N)[c] - 0.5) * n[0]);
  };
  const Agreement a = decode_vs_runtime(b, "godot4-packed", godot);
  EXPECT_LT(a.along_normal, 2e-3);                 // I_z exact; RGBA16F I_z and half-float storage
  EXPECT_LT(a.decode_rms, a.model_rms + 0.01);     // quantised planes add at most 1 % RMS
  EXPECT_LT(a.model_rms, 0.15);                    // the AHD model of this strongly lit scene
}

TEST(DecodeVsRuntime, BakerySh) {
  const WorldBake b("dvr_bakery");
  write_bakery_sh(b.w, b.base());
  const ImageF l0 = read_image(b.file("_L0.hdr")), lx = read_image(b.file("_L1x.tga")),
               ly = read_image(b.file("_L1y.tga")), lz = read_image(b.file("_L1z.tga"));
  // Bakery's BakerySH: L1 = (t·2 − 1)·L0·2 per axis, sh = L0 + n·L1 (Unity world axes).
  const Runtime bakery = [&](size_t i, int c, const double n[3]) {
    const double L0 = l0.data[i * l0.channels + c];
    auto l1 = [&](const ImageF& t) { return (t.data[i * t.channels + c] * 2 - 1) * L0 * 2; };
    return L0 + n[0] * l1(lx) + n[1] * l1(ly) + n[2] * l1(lz);
  };
  const Agreement a = decode_vs_runtime(b, "bakery-sh", bakery);
  EXPECT_LT(a.along_normal, 2e-3);
  EXPECT_LT(a.decode_rms, a.model_rms + 0.01);
  EXPECT_LT(a.model_rms, 0.15);
}
