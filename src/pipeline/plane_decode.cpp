#include "pipeline/plane_decode.h"

#include <algorithm>

#include "codecs/octahedral.h"
#include "core/error.h"
#include "fit/ahd_decode.h"
#include "fit/lowres_fit.h"
#include "pipeline/manifest.h"
#include "pipeline/plane_codec.h"
#include "pipeline/plane_scale.h"

namespace ahd {
namespace {

// One texel's decoded plane values → (I_z, d, ratio), the one rule for whole levels and texels.
// dir_ratio: the packed plane's 4 channels, or dir's 2 then ratio's `ratio_channels`.
void texel_values(const float* iz_v, const float* dir_v, const float* ratio_v, int ratio_channels, int ratio_first,
                  bool ratio_rgb, float iz[3], float d[3], float ratio[3]) {
  for (int c = 0; c < 3; ++c) iz[c] = iz_v[c];
  if (!dir_v) {  // a plain lightmap (no directional planes): pure ambient, d = z
    d[0] = d[1] = 0, d[2] = 1;
    ratio[0] = ratio[1] = ratio[2] = 1;
    return;
  }
  unit_uv_to_dir(dir_v, d);
  for (int c = 0; c < 3; ++c) {
    const int ch = ratio_rgb ? ratio_first + c : ratio_first;
    ratio[c] = ratio_v[std::min(ch, ratio_channels - 1)];
  }
}

// A decoded side plane smaller than I_z, sampled as a GPU samples it at every texel centre of the
// w×h I_z level: bilinear, clamp to edge, the same normalised UV (fit/lowres_fit.h bilinear_tap).
ImageF upsampled(const ImageF& img, int w, int h) {
  if (img.width == w && img.height == h) return img;
  ImageF out(w, h, img.channels);
  bilinear_upsample(img.data.data(), img.width, img.height, img.channels, w, h, out.data.data());
  return out;
}

// Texel (x, y) of a w×h level sampled from plane `tl` (of format f) as upsampled() samples it,
// decoding only the blocks of its (up to four) taps.
void sample_plane_texel(PixelFormat f, const TextureLevel& tl, uint32_t w, uint32_t h, uint32_t x, uint32_t y,
                        float out[4]) {
  if (tl.width == w && tl.height == h) return decode_plane_texel(f, tl, x, y, out);
  const BilinearTap tx = bilinear_tap(int(w), int(tl.width), int(x)), ty = bilinear_tap(int(h), int(tl.height), int(y));
  float v00[4], v10[4], v01[4], v11[4];
  decode_plane_texel(f, tl, uint32_t(tx.x0), uint32_t(ty.x0), v00);
  decode_plane_texel(f, tl, uint32_t(tx.x1), uint32_t(ty.x0), v10);
  decode_plane_texel(f, tl, uint32_t(tx.x0), uint32_t(ty.x1), v01);
  decode_plane_texel(f, tl, uint32_t(tx.x1), uint32_t(ty.x1), v11);
  for (int c = 0; c < format_info(f).channels; ++c) {
    const double top = (1.0 - tx.w1) * v00[c] + tx.w1 * v10[c];
    const double bottom = (1.0 - tx.w1) * v01[c] + tx.w1 * v11[c];
    out[c] = float((1.0 - ty.w1) * top + ty.w1 * bottom);
  }
}

}  // namespace

void unit_uv_to_dir(const float uv01[2], float d[3]) {
  const double uv[2] = {uv01[0] * 2.0 - 1.0, uv01[1] * 2.0 - 1.0};
  double dd[3];
  hemi_oct_decode(uv, dd);
  for (int i = 0; i < 3; ++i) d[i] = float(dd[i]);
}

DecodedPlanes decode_level(const CodedLevel& lv, bool ratio_rgb) {
  const ImageF izi = decode_plane(lv.iz_format, *lv.iz);
  DecodedPlanes out;
  out.width = izi.width, out.height = izi.height;
  const size_t n = izi.texels();
  out.iz.resize(n * 3);
  out.d.resize(n * 3);
  out.ratio.resize(n * 3);
  ImageF di, ri;
  int ratio_first = 0;
  if (lv.dirratio) {
    di = upsampled(decode_plane(lv.dirratio_format, *lv.dirratio), out.width, out.height);
    ratio_first = 2;
  } else if (lv.dir && lv.ratio) {
    di = upsampled(decode_plane(lv.dir_format, *lv.dir), out.width, out.height);
    ri = upsampled(decode_plane(lv.ratio_format, *lv.ratio), out.width, out.height);
  }
  const ImageF& rimg = lv.dirratio ? di : ri;
  const bool directional = di.texels() != 0;
  if (directional && (di.width != out.width || di.height != out.height || rimg.width != out.width ||
                      rimg.height != out.height))
    throw Error("planes of one conversion differ in size");
  for (size_t i = 0; i < n; ++i)
    texel_values(&izi.data[i * izi.channels], directional ? &di.data[i * di.channels] : nullptr,
                 directional ? &rimg.data[i * rimg.channels] : nullptr, rimg.channels, ratio_first, ratio_rgb,
                 &out.iz[i * 3], &out.d[i * 3], &out.ratio[i * 3]);
  return out;
}

void decode_texel(const CodedLevel& lv, bool ratio_rgb, uint32_t x, uint32_t y, float iz[3], float d[3],
                  float ratio[3]) {
  float izv[4], dv[4], rv[4];
  decode_plane_texel(lv.iz_format, *lv.iz, x, y, izv);
  const uint32_t w = lv.iz->width, h = lv.iz->height;
  if (lv.dirratio) {
    sample_plane_texel(lv.dirratio_format, *lv.dirratio, w, h, x, y, dv);
    texel_values(izv, dv, dv, format_info(lv.dirratio_format).channels, 2, ratio_rgb, iz, d, ratio);
  } else if (lv.dir && lv.ratio) {
    sample_plane_texel(lv.dir_format, *lv.dir, w, h, x, y, dv);
    sample_plane_texel(lv.ratio_format, *lv.ratio, w, h, x, y, rv);
    texel_values(izv, dv, rv, format_info(lv.ratio_format).channels, 0, ratio_rgb, iz, d, ratio);
  } else {
    texel_values(izv, nullptr, nullptr, 1, 0, ratio_rgb, iz, d, ratio);
  }
}

DecodedPlanes decode_planes(const std::vector<Plane>& planes, bool ratio_rgb, int level) {
  const Plane *iz = nullptr, *dir = nullptr, *ratio = nullptr, *dirratio = nullptr;
  for (const Plane& p : planes) {
    if (p.name == "iz") iz = &p;
    if (p.name == "dir") dir = &p;
    if (p.name == "ratio") ratio = &p;
    if (p.name == "dirratio") dirratio = &p;
  }
  if (!iz) throw Error("conversion has no iz plane");
  // Everything is validated before any texel is decoded (issue 15: an R8 "iz" plane from a hostile
  // manifest was read past its end): each format must fit its role, and every plane must have the
  // same mip chain, each level of the chain's size — except that the direction and ratio planes may
  // be ceil(W/s) x ceil(H/s), s = 2 or 4, with their own (possibly shorter) chain (pipeline/plane_scale.h).
  const RatioForm form = ratio_rgb ? RatioForm::Rgb : RatioForm::Luminance;
  if (iz->texture.levels.empty()) throw Error("plane iz has no levels");
  const uint32_t w0 = iz->texture.levels[0].width, h0 = iz->texture.levels[0].height;
  const Plane* side0 = dirratio ? dirratio : dir;
  for (const Plane* p : {iz, dir, ratio, dirratio}) {
    if (!p) continue;
    const std::string why = plane_format_problem(p->name, p->texture.format, form);
    if (!why.empty()) throw Error(why);
    uint32_t pw0 = w0, ph0 = h0;
    size_t levels = iz->texture.levels.size();
    if (p != iz && !p->texture.levels.empty()) {
      pw0 = p->texture.levels[0].width, ph0 = p->texture.levels[0].height;
      const TextureLevel& s0 = side0->texture.levels.empty() ? p->texture.levels[0] : side0->texture.levels[0];
      if (side_plane_scale(w0, h0, pw0, ph0) == 0 || pw0 != s0.width || ph0 != s0.height)
        throw Error("planes of one conversion differ in size (plane " + p->name + ", level 0)");
      levels = scaled_plane_levels(uint32_t(levels), pw0, ph0);
    }
    if (p->texture.levels.size() != levels) throw Error("planes of one conversion differ in level count");
    for (size_t l = 0; l < p->texture.levels.size(); ++l) {
      const TextureLevel& lv = p->texture.levels[l];
      if (pw0 == 0 || ph0 == 0 || lv.width != std::max(1u, pw0 >> l) || lv.height != std::max(1u, ph0 >> l))
        throw Error("planes of one conversion differ in size (plane " + p->name + ", level " + std::to_string(l) + ")");
    }
  }
  if (!dirratio && (dir != nullptr) != (ratio != nullptr)) throw Error("a dir plane needs its ratio plane and back");
  auto level_of = [&](const Plane* p) -> const TextureLevel& {
    if (level < 0 || size_t(level) >= iz->texture.levels.size())
      throw Error("plane " + p->name + " has no mip level " + std::to_string(level));
    // A shorter low-res chain: its last level serves the I_z levels past it (a GPU clamps the LOD).
    return p->texture.levels[std::min(size_t(level), p->texture.levels.size() - 1)];
  };
  CodedLevel lv;
  lv.iz_format = iz->texture.format;
  lv.iz = &level_of(iz);
  if (dirratio) {
    lv.dirratio_format = dirratio->texture.format;
    lv.dirratio = &level_of(dirratio);
  } else if (dir && ratio) {
    lv.dir_format = dir->texture.format;
    lv.dir = &level_of(dir);
    lv.ratio_format = ratio->texture.format;
    lv.ratio = &level_of(ratio);
  }
  return decode_level(lv, ratio_rgb);
}

std::vector<AhdLobe> lobes_from_planes(const DecodedPlanes& p, double dz_min) {
  std::vector<AhdLobe> lobes(p.iz.size() / 3);
  for (size_t i = 0; i < lobes.size(); ++i)
    decode_colours(&p.iz[i * 3], &p.d[i * 3], &p.ratio[i * 3], dz_min, lobes[i].ca, lobes[i].cd, lobes[i].d);
  return lobes;
}

}  // namespace ahd
