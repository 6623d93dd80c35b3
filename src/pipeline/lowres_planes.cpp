#include "pipeline/lowres_planes.h"

#include <algorithm>
#include <cmath>

#include "codecs/octahedral.h"
#include "core/parallel.h"
#include "fit/ahd_decode.h"
#include "fit/lowres_fit.h"
#include "mips/dilate.h"

namespace ahd {

LowResPlanes lowres_level_planes(const FittedLevel& lv, const TextureLevel& iz, const Profile& profile,
                                 const PipelineOptions& opt, int lw, int lh) {
  const ShImage& sh = lv.sh;
  const int w = sh.width, h = sh.height;
  const int threads = opt.threads;
  PlaneCodecOptions codec = opt.codec;
  codec.threads = threads;
  LowResPlanes out;
  // 1. Directions on the mean SH of each low-res texel's box, the uncovered ones dilated (as
  //    dilate_ahd does: the 3-vector mean, renormalised, the horizon rule).
  const LowResDirections dirs = lowres_directions(sh, lw, lh, opt.fit, threads);
  ImageF dimg(lw, lh, 3);
  dimg.data = dirs.d;
  dilate(dimg, dirs.coverage, threads);
  ImageF uv(lw, lh, 2);
  for (size_t k = 0; k < dimg.texels(); ++k) {
    double d[3] = {dimg.data[k * 3], dimg.data[k * 3 + 1], dimg.data[k * 3 + 2]};
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (len > 0) {
      for (double& v : d) v /= len;
    } else {
      d[0] = d[1] = 0, d[2] = 1;
    }
    tilt_above_horizon(d, opt.fit.dz_min);
    const float df[3] = {float(d[0]), float(d[1]), float(d[2])};
    hemi_oct_unit_uv(df, &uv.data[k * 2]);
  }
  // 2. I_z as the decoder reads it (closed loop) or as fitted (open loop).
  std::vector<float> iz_full(size_t(w) * size_t(h) * 3);
  if (opt.closed_loop) {
    const ImageF izd = decode_plane(profile.iz, iz);
    for (size_t i = 0; i < sh.texels(); ++i)
      for (int c = 0; c < 3; ++c) iz_full[i * 3 + size_t(c)] = std::max(0.0f, izd.data[i * size_t(izd.channels) + size_t(c)]);
  } else {
    for (size_t i = 0; i < sh.texels(); ++i) fitted_iz(lv, i, &iz_full[i * 3]);
  }
  std::vector<float> uv_full(size_t(w) * size_t(h) * 2);
  std::vector<float> d_full(size_t(w) * size_t(h) * 3);
  // 3. The directions moved to what lowers the error of the bilinearly sampled planes (with the
  //    ratio solved alongside; the ratio is solved again below against the coded direction).
  if (kLowResDirectionSweeps > 0) {
    bilinear_upsample(uv.data.data(), lw, lh, 2, w, h, uv_full.data());
    parallel_for(sh.texels(), threads, 4096, [&](size_t i) { unit_uv_to_dir(&uv_full[i * 2], &d_full[i * 3]); });
    const RatioQuadratics q0 = ratio_quadratics(sh, iz_full.data(), d_full.data(), opt.fit, threads);
    ImageF r0(lw, lh, q0.channels);
    r0.data = lowres_box_ratio(q0, lw, lh);
    dilate(r0, dirs.coverage, threads);
    lowres_direction_sweeps(sh, iz_full.data(), lw, lh, uv.data, r0.data, opt.fit, kLowResDirectionSweeps, threads);
  }
  // 4. The direction as the decoder reads it at every full-res texel: the coded plane's values
  //    sampled bilinearly (the packed RGBA8 plane: the uv's 8-bit rounding).
  ImageF uv_dec;
  if (profile.packed_dir_ratio) {
    uv_dec = uv;
    for (float& v : uv_dec.data) v = float(std::lround(v * 255.0f)) / 255.0f;
  } else {
    out.dir = encode_plane(profile.dir, uv, codec, nullptr);
    uv_dec = decode_plane(profile.dir, out.dir);
  }
  bilinear_upsample(uv_dec.data.data(), lw, lh, 2, w, h, uv_full.data());
  parallel_for(sh.texels(), threads, 4096, [&](size_t i) { unit_uv_to_dir(&uv_full[i * 2], &d_full[i * 3]); });
  uv_full = {};
  // 5. The ratio against the decoded I_z and direction, from its box least squares, then sweeps.
  const RatioQuadratics q = ratio_quadratics(sh, iz_full.data(), d_full.data(), opt.fit, threads);
  iz_full = {};
  d_full = {};
  ImageF rimg(lw, lh, q.channels);
  rimg.data = lowres_box_ratio(q, lw, lh);
  dilate(rimg, dirs.coverage, threads);
  lowres_ratio_sweeps(q, lw, lh, rimg.data, kLowResRatioSweeps, threads);
  if (!profile.packed_dir_ratio) {
    out.ratio = encode_plane(profile.ratio, rimg, codec, nullptr);
    return out;
  }
  ImageF packed(lw, lh, 4);
  for (size_t k = 0; k < packed.texels(); ++k) {
    packed.data[k * 4 + 0] = uv.data[k * 2 + 0];
    packed.data[k * 4 + 1] = uv.data[k * 2 + 1];
    packed.data[k * 4 + 2] = rimg.data[k * size_t(q.channels)];
    packed.data[k * 4 + 3] = 1.0f;
  }
  out.dirratio = encode_plane(profile.dirratio, packed, codec, nullptr);
  return out;
}

}  // namespace ahd
