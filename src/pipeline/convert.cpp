#include "pipeline/convert.h"

#include <chrono>
#include <cmath>

#include "codecs/octahedral.h"
#include "core/error.h"
#include "core/parallel.h"
#include "fit/ahd_decode.h"

namespace ahd {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

Texture single_level(PixelFormat f, TextureLevel lvl) {
  Texture t;
  t.format = f;
  t.levels.push_back(std::move(lvl));
  return t;
}

// Direction → hemi-octahedral uv in [0,1]² (what UNORM planes store).
void dir_to_unit_uv(const float d[3], float uv01[2]) {
  const double dd[3] = {d[0], d[1], std::max(0.0f, d[2])};
  double uv[2];
  hemi_oct_encode(dd, uv);
  uv01[0] = float(uv[0] * 0.5 + 0.5);
  uv01[1] = float(uv[1] * 0.5 + 0.5);
}

void unit_uv_to_dir(const float uv01[2], float d[3]) {
  const double uv[2] = {uv01[0] * 2.0 - 1.0, uv01[1] * 2.0 - 1.0};
  double dd[3];
  hemi_oct_decode(uv, dd);
  for (int i = 0; i < 3; ++i) d[i] = float(dd[i]);
}

std::vector<AhdLobe> lobes_from_fit(const AhdImage& a) {
  std::vector<AhdLobe> lobes(a.texels.size());
  for (size_t i = 0; i < a.texels.size(); ++i) {
    const AhdFit& f = a.texels[i];
    for (int c = 0; c < 3; ++c) {
      lobes[i].ca[c] = f.ca[c];
      lobes[i].cd[c] = f.cd[c];
      lobes[i].d[c] = f.d[c];
    }
  }
  return lobes;
}

}  // namespace

DecodedPlanes decode_planes(const std::vector<Plane>& planes, bool ratio_rgb, int level) {
  const Plane *iz = nullptr, *dir = nullptr, *ratio = nullptr, *dirratio = nullptr;
  for (const Plane& p : planes) {
    if (p.name == "iz") iz = &p;
    if (p.name == "dir") dir = &p;
    if (p.name == "ratio") ratio = &p;
    if (p.name == "dirratio") dirratio = &p;
  }
  if (!iz) throw Error("conversion has no iz plane");
  auto level_of = [&](const Plane* p) -> const TextureLevel& {
    if (level < 0 || size_t(level) >= p->texture.levels.size())
      throw Error("plane " + p->name + " has no mip level " + std::to_string(level));
    return p->texture.levels[size_t(level)];
  };
  const ImageF izi = decode_plane(iz->texture.format, level_of(iz));
  DecodedPlanes out;
  out.width = izi.width, out.height = izi.height;
  const size_t n = izi.texels();
  out.iz.resize(n * 3);
  out.d.assign(n * 3, 0.0f);
  out.ratio.assign(n * 3, 1.0f);
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) out.iz[i * 3 + c] = izi.data[i * izi.channels + c];
  ImageF di, ri;
  int ratio_channel = 0;
  if (dirratio) {
    di = decode_plane(dirratio->texture.format, level_of(dirratio));
    ri = di;
    ratio_channel = 2;
  } else if (dir && ratio) {
    di = decode_plane(dir->texture.format, level_of(dir));
    ri = decode_plane(ratio->texture.format, level_of(ratio));
  }
  if (di.texels() == 0) {
    // A plain lightmap (no directional planes): pure ambient, d = z.
    for (size_t i = 0; i < n; ++i) out.d[i * 3 + 2] = 1.0f;
    return out;
  }
  if (di.width != out.width || di.height != out.height || ri.width != out.width || ri.height != out.height)
    throw Error("planes of one conversion differ in size");
  for (size_t i = 0; i < n; ++i) {
    unit_uv_to_dir(&di.data[i * di.channels], &out.d[i * 3]);
    for (int c = 0; c < 3; ++c) {
      const int ch = ratio_rgb ? ratio_channel + c : ratio_channel;
      out.ratio[i * 3 + c] = ri.data[i * ri.channels + std::min(ch, ri.channels - 1)];
    }
  }
  return out;
}

std::vector<AhdLobe> lobes_from_planes(const DecodedPlanes& p, double dz_min) {
  std::vector<AhdLobe> lobes(p.iz.size() / 3);
  for (size_t i = 0; i < lobes.size(); ++i)
    decode_colours(&p.iz[i * 3], &p.d[i * 3], &p.ratio[i * 3], dz_min, lobes[i].ca, lobes[i].cd, lobes[i].d);
  return lobes;
}

ConvertResult convert(const ShImage& sh, const Profile& profile, const ConvertOptions& opt) {
  ConvertResult r;
  const int threads = opt.threads;
  const size_t n = sh.texels();
  const bool ratio_rgb = opt.fit.ratio_form == RatioForm::Rgb;
  if (profile.packed_dir_ratio && ratio_rgb)
    throw Error("profile " + profile.name + " packs one ratio channel; use the luminance ratio form");
  for (PixelFormat f : {profile.iz, profile.packed_dir_ratio ? profile.dirratio : profile.dir,
                        profile.packed_dir_ratio ? profile.dirratio : profile.ratio})
    if (!plane_format_supported(f))
      throw Error("profile " + profile.name + " needs format " + format_info(f).name +
                  ", which this build cannot encode yet");
  if (ratio_rgb && !profile.packed_dir_ratio && format_info(profile.ratio).channels < 3)
    throw Error("the RGB ratio form needs a 3- or 4-channel ratio format (profile " + profile.name + " has " +
                format_info(profile.ratio).name + ")");

  // 1. Fit.
  auto t0 = Clock::now();
  const AhdImage fit = fit_image(sh, opt.fit, threads, &r.fit_stats);
  r.timings.push_back({"fit", seconds_since(t0)});

  t0 = Clock::now();
  if (opt.measure) r.fit_error = measure_error(sh, lobes_from_fit(fit), threads);
  if (opt.measure && opt.measure_unconstrained) {
    std::vector<AhdLobe> lobes(n);
    parallel_for(n, threads, 1024, [&](size_t i) {
      IrradiancePoly p[3];
      local_polys(sh, i, p);
      const double d[3] = {fit.texels[i].d[0], fit.texels[i].d[1], fit.texels[i].d[2]};
      for (int c = 0; c < 3; ++c) {
        fit_channel_unconstrained(hemisphere_moments(p[c], d), &lobes[i].ca[c], &lobes[i].cd[c]);
        lobes[i].d[c] = d[c];
      }
    });
    r.unconstrained_error = measure_error(sh, lobes, threads);
  }
  if (opt.measure) r.timings.push_back({"measure fit", seconds_since(t0)});

  // 2. Quantise, closed loop: direction first, then I_z, then the ratio refitted against the
  //    DECODED direction and I_z.
  t0 = Clock::now();
  const int w = sh.width, h = sh.height;
  ImageF uv(w, h, 2), izi(w, h, 3);
  for (size_t i = 0; i < n; ++i) {
    dir_to_unit_uv(fit.texels[i].d, &uv.data[i * 2]);
    for (int c = 0; c < 3; ++c) izi.data[i * 3 + c] = fit.texels[i].iz[c];
  }
  Texture iz_tex = single_level(profile.iz, encode_plane(profile.iz, izi, opt.codec, &r.codec_stats));
  const ImageF iz_dec = decode_plane(profile.iz, iz_tex.levels[0]);

  // Direction: for packed profiles it shares a texture with the ratio, quantised per texel (RGBA8),
  // so its decoded value is known before the ratio is chosen.
  ImageF dir_dec;
  Texture dir_tex;
  if (!profile.packed_dir_ratio) {
    dir_tex = single_level(profile.dir, encode_plane(profile.dir, uv, opt.codec));
    dir_dec = decode_plane(profile.dir, dir_tex.levels[0]);
  } else {
    dir_dec = ImageF(w, h, 2);
    for (size_t i = 0; i < n * 2; ++i) dir_dec.data[i] = std::lround(uv.data[i] * 255.0f) / 255.0f;
  }

  const int rch = ratio_rgb ? 3 : 1;
  ImageF ratio_closed(w, h, rch), ratio_open(w, h, rch);
  parallel_for(n, threads, 1024, [&](size_t i) {
    const AhdFit& f = fit.texels[i];
    for (int c = 0; c < rch; ++c) ratio_open.data[i * rch + c] = f.ratio[c];
    if (!opt.closed_loop) {
      for (int c = 0; c < rch; ++c) ratio_closed.data[i * rch + c] = f.ratio[c];
      return;
    }
    float dq[3];
    unit_uv_to_dir(&dir_dec.data[i * dir_dec.channels], dq);
    double d[3] = {dq[0], dq[1], dq[2]};
    tilt_above_horizon(d, opt.fit.dz_min);  // as the decoder will
    const double iz[3] = {std::max(0.0f, iz_dec.data[i * iz_dec.channels + 0]),
                          std::max(0.0f, iz_dec.data[i * iz_dec.channels + 1]),
                          std::max(0.0f, iz_dec.data[i * iz_dec.channels + 2])};
    IrradiancePoly p[3];
    local_polys(sh, i, p);
    const AhdFit g = fit_colours(p, d, iz, opt.fit);
    for (int c = 0; c < rch; ++c) ratio_closed.data[i * rch + c] = g.ratio[c];
  });

  auto make_planes = [&](const ImageF& ratio) {
    std::vector<Plane> planes;
    planes.push_back({"iz", iz_tex});
    if (profile.packed_dir_ratio) {
      ImageF packed(w, h, 4);
      for (size_t i = 0; i < n; ++i) {
        packed.data[i * 4 + 0] = uv.data[i * 2 + 0];
        packed.data[i * 4 + 1] = uv.data[i * 2 + 1];
        packed.data[i * 4 + 2] = ratio.data[i * rch];
        packed.data[i * 4 + 3] = 1.0f;
      }
      planes.push_back({"dirratio", single_level(profile.dirratio, encode_plane(profile.dirratio, packed, opt.codec))});
    } else {
      planes.push_back({"dir", dir_tex});
      planes.push_back({"ratio", single_level(profile.ratio, encode_plane(profile.ratio, ratio, opt.codec))});
    }
    return planes;
  };
  r.planes = make_planes(ratio_closed);
  r.timings.push_back({"quantise", seconds_since(t0)});

  if (!opt.measure) return r;
  t0 = Clock::now();
  r.final_error = measure_error(sh, lobes_from_planes(decode_planes(r.planes, ratio_rgb), opt.fit.dz_min), threads);
  if (opt.measure_open_loop) {
    r.open_loop_error =
        measure_error(sh, lobes_from_planes(decode_planes(make_planes(ratio_open), ratio_rgb), opt.fit.dz_min), threads);
  }
  r.timings.push_back({"measure quantised", seconds_since(t0)});
  return r;
}

}  // namespace ahd
