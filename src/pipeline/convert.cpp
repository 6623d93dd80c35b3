#include "pipeline/convert.h"

#include <chrono>
#include <cmath>
#include <cstdio>

#include "codecs/octahedral.h"
#include "core/error.h"
#include "core/large_buffer.h"
#include "core/parallel.h"
#include "fit/ahd_decode.h"
#include "mips/mips.h"
#include "pipeline/lowres_planes.h"
#include "pipeline/manifest.h"
#include "pipeline/plane_scale.h"

namespace ahd {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}


// I_z alone: d = z, ratio = 1, so I(n) = I_z for every normal.
AhdLobe ambient_only_lobe(const AhdFit& f) {
  AhdLobe l;
  for (int c = 0; c < 3; ++c) {
    l.ca[c] = std::max(0.0f, f.iz[c]);
    l.cd[c] = 0;
    l.d[c] = c == 2 ? 1 : 0;
  }
  return l;
}

// What the fitted (unquantised) planes decode to, as the reference decoder reads them.
AhdLobe lobe_of_fit(const AhdFit& f, double dz_min) {
  AhdLobe l;
  decode_colours(f.iz, f.d, f.ratio, dz_min, l.ca, l.cd, l.d);
  return l;
}

}  // namespace

void check_profile(const Profile& profile, const PipelineOptions& opt) {
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
}

namespace {

// Rows [y0, y1) of a coded level as a level of its own (y0 a multiple of the block height): block
// rows and texel rows are stored one after another, so the rows are one byte range.
TextureLevel level_rows(PixelFormat f, const TextureLevel& lvl, int y0, int y1) {
  const size_t begin = level_size_bytes(f, lvl.width, uint32_t(y0));
  const size_t size = level_size_bytes(f, lvl.width, uint32_t(y1 - y0));
  TextureLevel s;
  s.width = lvl.width;
  s.height = uint32_t(y1 - y0);
  s.data.assign(lvl.data.begin() + std::ptrdiff_t(begin), lvl.data.begin() + std::ptrdiff_t(begin + size));
  return s;
}

// Rows per band where a level is encoded or decoded piecewise: a multiple of every block height.
constexpr int kBandRows = 64;

// Encodes a w×h plane a band of kBandRows rows at a time: fill(y0, band, threads) writes rows
// [y0, y0 + band.height) on up to `threads` threads. Block rows encode on their own and each band's
// bytes go to their own place, so the bytes are those of encoding the whole plane at once, whatever
// the thread count. With a band or more per thread, bands run side by side, each filled and encoded
// on one thread: the fill and the encoding overlap, and no threads start for each band (a 2048²
// plain map's quantise stage, 2 threads: 0.091–0.101 → 0.060–0.073 s). Smaller levels give every
// thread to each band.
template <class Fill>
TextureLevel encode_banded(PixelFormat f, int w, int h, int channels, const PlaneCodecOptions& codec,
                           PlaneCodecStats* stats, const Fill& fill) {
  TextureLevel out;
  out.width = uint32_t(w);
  out.height = uint32_t(h);
  // Advised for huge pages: a level-0 plane of a 1024² map is 8 MB, 2 000 page faults in 4 KB pages.
  assign_large(out.data, level_size_bytes(f, out.width, out.height), uint8_t(0));
  const int bands = (h + kBandRows - 1) / kBandRows;
  const int threads = resolve_threads(codec.threads);
  const bool side_by_side = bands >= threads;
  PlaneCodecOptions band_codec = codec;
  if (side_by_side) band_codec.threads = 1;
  std::vector<PlaneCodecStats> band_stats(static_cast<size_t>(bands));
  parallel_for(size_t(bands), side_by_side ? threads : 1, 1, [&](size_t b) {
    const int y0 = int(b) * kBandRows;
    ImageF band(w, std::min(h, y0 + kBandRows) - y0, channels);
    fill(y0, band, band_codec.threads);
    const TextureLevel part = encode_plane(f, band, band_codec, &band_stats[b]);
    std::copy(part.data.begin(), part.data.end(), out.data.begin() + std::ptrdiff_t(level_size_bytes(f, out.width, uint32_t(y0))));
  });
  if (stats)
    for (const PlaneCodecStats& s : band_stats) stats->clamped += s.clamped, stats->non_finite += s.non_finite;
  return out;
}

// Planes of one level, closed loop: direction first, then I_z, then the ratio refitted against
// the DECODED direction and I_z (covered texels; uncovered ones keep their dilated ratio).
struct LevelPlanes {
  TextureLevel iz, dir, ratio, dirratio;           // closed loop (or open when !closed_loop)
  TextureLevel ratio_open, dirratio_open;          // open loop, for the report
};

// side_w × side_h: the size of the direction and ratio planes at this level when the profile stores
// them at a lower resolution (dir_ratio_scale > 1; 0 × 0: their chain has ended, pipeline/plane_scale.h).
LevelPlanes quantise_level(const FittedLevel& lv, const Profile& profile, const PipelineOptions& opt, bool directional,
                           PlaneCodecStats* stats, int side_w = 0, int side_h = 0) {
  const ShImage& sh = lv.sh;
  const int w = sh.width, h = sh.height;
  const bool ratio_rgb = opt.fit.ratio_form == RatioForm::Rgb;
  PlaneCodecOptions codec = opt.codec;
  codec.threads = opt.threads;
  LevelPlanes out;
  // I_z: a float copy of one band of rows at a time, never of the whole level.
  out.iz = encode_banded(profile.iz, w, h, 3, codec, stats, [&](int y0, ImageF& band, int threads) {
    const size_t first = size_t(y0) * size_t(w);
    // 4096 texels per call (one std::function call per texel was 7 % of a plain map's conversion).
    constexpr size_t kSpan = 4096;
    parallel_for((band.texels() + kSpan - 1) / kSpan, threads, 1, [&](size_t c) {
      const size_t b = c * kSpan, e = std::min(band.texels(), (c + 1) * kSpan);
      if (lv.ahd.empty()) return ambient_level_iz_span(lv.sh, first + b, e - b, &band.data[b * 3]);
      for (size_t j = b; j < e; ++j) fitted_iz(lv, first + j, &band.data[j * 3]);
    });
  });
  if (!directional) return out;
  if (profile.dir_ratio_scale > 1) {  // low-res planes (pipeline/lowres_planes.h)
    if (side_w == 0) return out;
    LowResPlanes lp = lowres_level_planes(lv, out.iz, profile, opt, side_w, side_h);
    out.dir = std::move(lp.dir), out.ratio = std::move(lp.ratio), out.dirratio = std::move(lp.dirratio);
    if (opt.measuring_baselines()) out.ratio_open = out.ratio, out.dirratio_open = out.dirratio;  // no open loop apart
    return out;
  }
  // The direction and ratio planes are made a band of rows at a time too: no float image of the
  // whole level beside the fit (8 + 4 bytes a texel at level 0).
  auto uv_rows = [&](int y0, ImageF& band, int threads) {
    const size_t first = size_t(y0) * size_t(w);
    parallel_for(band.texels(), threads, 4096,
                 [&](size_t j) { hemi_oct_unit_uv(fitted_texel(lv, first + j).d, &band.data[j * 2]); });
  };
  if (!profile.packed_dir_ratio) out.dir = encode_banded(profile.dir, w, h, 2, codec, nullptr, uv_rows);
  const int rch = ratio_rgb ? 3 : 1;
  // The ratio of rows [y0, y0 + ratio.height): the fit's (open loop) or, closed loop, refitted for
  // the covered texels against the DECODED direction and I_z of those rows (blocks decode on their
  // own, so the values are those of whole-plane decoding); uncovered texels keep their dilated ratio.
  auto ratio_rows = [&](int y0, ImageF& ratio, bool closed, int threads) {
    const int y1 = y0 + ratio.height;
    const size_t first = size_t(y0) * size_t(w);
    for (size_t j = 0; j < ratio.texels(); ++j) {
      const AhdFit f = fitted_texel(lv, first + j);
      for (int c = 0; c < rch; ++c) ratio.data[j * rch + c] = f.ratio[c];
    }
    if (!closed) return;
    const ImageF iz_dec = decode_plane(profile.iz, level_rows(profile.iz, out.iz, y0, y1));
    ImageF dir_dec;
    if (!profile.packed_dir_ratio) {
      dir_dec = decode_plane(profile.dir, level_rows(profile.dir, out.dir, y0, y1));
    } else {
      // The packed plane is RGBA8: the direction's decoded value is its 8-bit rounding.
      dir_dec = ImageF(w, y1 - y0, 2);
      uv_rows(y0, dir_dec, threads);
      for (float& v : dir_dec.data) v = float(std::lround(v * 255.0f)) / 255.0f;
    }
    parallel_for(ratio.texels(), threads, 1024, [&](size_t j) {
      const size_t i = first + j;
      if (!sh.coverage[i]) return;
      float dq[3];
      unit_uv_to_dir(&dir_dec.data[j * dir_dec.channels], dq);
      double d[3] = {dq[0], dq[1], dq[2]};
      tilt_above_horizon(d, opt.fit.dz_min);  // as the decoder will
      double iz[3];
      for (int c = 0; c < 3; ++c) iz[c] = std::max(0.0f, iz_dec.data[j * iz_dec.channels + c]);
      IrradiancePoly p[3];
      local_polys(sh, i, p);
      const AhdFit g = fit_colours(p, d, iz, opt.fit);
      for (int c = 0; c < rch; ++c) ratio.data[j * rch + c] = g.ratio[c];
    });
  };
  const bool open_too = opt.measuring_baselines();  // the open-loop plane, for the report only
  if (profile.packed_dir_ratio) {
    auto packed_rows = [&](bool closed) {
      return [&, closed](int y0, ImageF& band, int threads) {
        ImageF uv(w, band.height, 2), ratio(w, band.height, rch);
        uv_rows(y0, uv, threads);
        ratio_rows(y0, ratio, closed, threads);
        for (size_t j = 0; j < band.texels(); ++j) {
          band.data[j * 4 + 0] = uv.data[j * 2 + 0];
          band.data[j * 4 + 1] = uv.data[j * 2 + 1];
          band.data[j * 4 + 2] = ratio.data[j * rch];
          band.data[j * 4 + 3] = 1.0f;
        }
      };
    };
    out.dirratio = encode_banded(profile.dirratio, w, h, 4, codec, nullptr, packed_rows(opt.closed_loop));
    if (open_too) out.dirratio_open = encode_banded(profile.dirratio, w, h, 4, codec, nullptr, packed_rows(false));
  } else {
    auto plane_rows = [&](bool closed) {
      return [&, closed](int y0, ImageF& band, int threads) { ratio_rows(y0, band, closed, threads); };
    };
    out.ratio = encode_banded(profile.ratio, w, h, rch, codec, nullptr, plane_rows(opt.closed_loop));
    if (open_too) out.ratio_open = encode_banded(profile.ratio, w, h, rch, codec, nullptr, plane_rows(false));
  }
  return out;
}

// The planes of every level, the levels' bytes moved in. open_loop: the ratio planes of the
// unquantised fit's ratio (for the report) instead of the closed loop's.
std::vector<Plane> planes_of(const Profile& profile, std::vector<LevelPlanes>&& lv, bool directional) {
  auto texture = [&](PixelFormat f, TextureLevel LevelPlanes::*member) {
    Texture t;
    t.format = f;
    for (auto& l : lv)
      if ((l.*member).width != 0) t.levels.push_back(std::move(l.*member));  // a low-res chain may end first
    return t;
  };
  std::vector<Plane> planes;
  planes.push_back({"iz", texture(profile.iz, &LevelPlanes::iz)});
  if (!directional) return planes;
  if (profile.packed_dir_ratio) {
    planes.push_back({"dirratio", texture(profile.dirratio, &LevelPlanes::dirratio)});
  } else {
    planes.push_back({"dir", texture(profile.dir, &LevelPlanes::dir)});
    planes.push_back({"ratio", texture(profile.ratio, &LevelPlanes::ratio)});
  }
  return planes;
}

// One level's coded planes as the decoder reads them; open_loop: with the open-loop ratio. `side`:
// the level holding the direction and ratio planes when it is not `p` (a low-res chain that ended).
CodedLevel coded_level(const Profile& profile, const LevelPlanes& iz_level, bool directional, bool open_loop,
                       const LevelPlanes* side = nullptr) {
  CodedLevel c;
  c.iz_format = profile.iz;
  c.iz = &iz_level.iz;
  if (!directional) return c;
  const LevelPlanes& p = side ? *side : iz_level;
  if (profile.packed_dir_ratio) {
    c.dirratio_format = profile.dirratio;
    c.dirratio = open_loop ? &p.dirratio_open : &p.dirratio;
  } else {
    c.dir_format = profile.dir;
    c.dir = &p.dir;
    c.ratio_format = profile.ratio;
    c.ratio = open_loop ? &p.ratio_open : &p.ratio;
  }
  return c;
}

// Lobes against the SH as the options ask: every covered texel (Full) or the fixed sample (Estimate).
ErrorReport measure_lobes(const ShImage& sh, const LobeAt& lobe, const PipelineOptions& opt) {
  return opt.measure == Measure::Full ? measure_error(sh, lobe, opt.threads) : estimate_error(sh, lobe, opt.threads);
}

// One level's coded planes against the level's SH. Full: the whole level decoded; Estimate: only
// the blocks of the sampled texels (the same values: blocks decode on their own), or the whole
// level where the sample holds a quarter of its texels or more (from 128² down at the default
// sample: each sampled texel would decode its blocks again, 16 times a block at 64²).
ErrorReport measure_coded(const ShImage& sh, const CodedLevel& coded, const PipelineOptions& opt) {
  const bool rgb = opt.fit.ratio_form == RatioForm::Rgb;
  if (opt.measure == Measure::Full || size_t(kErrorSampleSize) * 4 >= sh.texels()) {
    const DecodedPlanes p = decode_level(coded, rgb);
    const LobeAt lobe = [&](size_t i) {
      AhdLobe l;
      decode_colours(&p.iz[i * 3], &p.d[i * 3], &p.ratio[i * 3], opt.fit.dz_min, l.ca, l.cd, l.d);
      return l;
    };
    return measure_lobes(sh, lobe, opt);
  }
  return estimate_error(sh, [&](size_t i) {
    float iz[3], d[3], ratio[3];
    decode_texel(coded, rgb, uint32_t(i % size_t(sh.width)), uint32_t(i / size_t(sh.width)), iz, d, ratio);
    AhdLobe l;
    decode_colours(iz, d, ratio, opt.fit.dz_min, l.ca, l.cd, l.d);
    return l;
  }, opt.threads);
}

// Keep, drop, or (Auto) measure whether I_z alone is close enough to the SH.
void decide_direction(const FittedLevel& level0, const PipelineOptions& opt, PipelineResult* r) {
  char why[160];
  switch (opt.direction) {
    case DirectionPlanes::Keep:
      r->directional = true;
      r->direction_reason = "kept (--direction keep)";
      return;
    case DirectionPlanes::Drop:
      r->directional = false;
      r->direction_reason = "dropped (--direction drop)";
      return;
    case DirectionPlanes::Auto: {
      // No L1/L2 at all (plain lightmaps): I_z alone is exact, decided without evaluating anything.
      // Otherwise the I_z-alone error over the fixed sample (every covered texel of images up to
      // kErrorSampleSize of them), with the early exit; lobes made on the fly (no image of them).
      if (sh_is_constant(level0.sh)) {
        r->directional = false;
      } else {
        r->directional = sampled_relative_p99_exceeds(
            level0.sh, [&](size_t i) { return ambient_only_lobe(fitted_texel(level0, i)); }, opt.ambient_threshold);
      }
      // An L0 image's fit is the ambient lobe itself (ratio 1: C_a = I_z ≥ 0, C_d = 0), so its
      // measured fit error (measure_fit, which runs first) is this figure, texel for texel.
      if (opt.measuring() && level0.sh.coeffs == 1 && r->fit_error.population != 0)
        r->ambient_error = r->fit_error;
      else if (opt.measuring())
        r->ambient_error = measure_lobes(level0.sh, [&](size_t i) { return ambient_only_lobe(fitted_texel(level0, i)); }, opt);
      std::snprintf(why, sizeof why, "%s: I_z alone differs from the SH by %s threshold %.3g (relative RMSE p99)",
                    r->directional ? "kept" : "dropped", r->directional ? "more than the" : "no more than the",
                    opt.ambient_threshold);
      r->direction_reason = why;
      return;
    }
  }
}

}  // namespace

std::vector<AhdLobe> ambient_only_lobes(const FittedLevel& level) {
  std::vector<AhdLobe> lobes(level.sh.texels());
  for (size_t i = 0; i < lobes.size(); ++i) lobes[i] = ambient_only_lobe(fitted_texel(level, i));
  return lobes;
}

ErrorReport ambient_only_error(const FittedLevel& level, int threads) {
  return measure_error(level.sh, ambient_only_lobes(level), threads);
}

std::vector<FittedLevel> fit_levels(const ShImage& sh, const PipelineOptions& opt, PipelineResult* r) {
  return fit_levels(ShImage(sh), opt, r);
}

namespace {

// The fitted level 0 against its SH (and the unconstrained baseline), as the options ask.
void measure_fit(const FittedLevel& level0, const PipelineOptions& opt, PipelineResult* r) {
  const ShImage& sh = level0.sh;
  // Lobes made texel by texel as they are measured: no image of them (72 bytes a texel).
  r->fit_error = measure_lobes(sh, [&](size_t i) { return lobe_of_fit(fitted_texel(level0, i), opt.fit.dz_min); }, opt);
  if (!opt.measuring_baselines()) return;
  r->unconstrained_error = measure_error(sh, [&](size_t i) {
    AhdLobe l;
    IrradiancePoly p[3];
    local_polys(sh, i, p);
    const AhdFit f = fitted_texel(level0, i);
    const double d[3] = {f.d[0], f.d[1], f.d[2]};
    for (int c = 0; c < 3; ++c) {
      fit_channel_unconstrained(hemisphere_moments(p[c], d), &l.ca[c], &l.cd[c]);
      l.d[c] = d[c];
    }
    return l;
  }, opt.threads);
}

// Quantises and measures the levels of a chain one at a time, level 0 first, so that a caller can
// drop each level before it fits the next: convert(ShImage&&) streams the chain through it,
// quantise_levels hands it a stored chain. Fills the direction decision, planes, errors, timings.
class ChainEncoder {
 public:
  ChainEncoder(const Profile& profile, const PipelineOptions& opt, PipelineResult* r, double chain_texels)
      : profile_(profile), opt_(opt), r_(r), all_(chain_texels) {}

  void add(const FittedLevel& level) {
    auto t0 = Clock::now();
    if (levels_.empty()) {
      decide_direction(level, opt_, r_);
      decide_ += seconds_since(t0);
      t0 = Clock::now();
    }
    opt_.step("encode", done_ / all_);
    int side_w = 0, side_h = 0;  // the low-res direction and ratio planes' size at this level
    if (profile_.dir_ratio_scale > 1) {
      if (levels_.empty()) {
        side_w0_ = scaled_plane_size(uint32_t(level.sh.width), profile_.dir_ratio_scale);
        side_h0_ = scaled_plane_size(uint32_t(level.sh.height), profile_.dir_ratio_scale);
      }
      const uint32_t l = uint32_t(levels_.size());
      if (l < full_mip_count(side_w0_, side_h0_))
        side_w = int(std::max(1u, side_w0_ >> l)), side_h = int(std::max(1u, side_h0_ >> l));
    }
    levels_.push_back(quantise_level(level, profile_, opt_, r_->directional, &r_->codec_stats, side_w, side_h));
    if (opt_.coverage_plane) {
      const Image8 c = coverage_plane(level.sh.width, level.sh.height, level.sh.coverage);
      coverage_.levels.push_back({uint32_t(c.width), uint32_t(c.height), c.data});
    }
    quantise_ += seconds_since(t0);
    done_ += double(level.sh.texels());
    if (!opt_.measuring()) return;
    t0 = Clock::now();
    const LevelPlanes& p = levels_.back();
    // A low-res chain that ended: this level reads its last level (pipeline/plane_scale.h).
    const LevelPlanes* side = nullptr;
    if (profile_.dir_ratio_scale > 1 && levels_.size() > full_mip_count(side_w0_, side_h0_))
      side = &levels_[full_mip_count(side_w0_, side_h0_) - 1];
    r_->level_error.push_back(measure_coded(level.sh, coded_level(profile_, p, r_->directional, false, side), opt_));
    if (levels_.size() == 1 && opt_.measuring_baselines() && r_->directional)
      r_->open_loop_error = measure_coded(level.sh, coded_level(profile_, p, true, true), opt_);
    measure_ += seconds_since(t0);
  }

  void finish() {
    opt_.step("encode", 1);
    r_->planes = planes_of(profile_, std::move(levels_), r_->directional);
    if (opt_.coverage_plane) {
      coverage_.format = PixelFormat::R8_UNORM;
      r_->planes.push_back({"coverage", std::move(coverage_)});
    }
    r_->timings.push_back({"direction decision", decide_});
    r_->timings.push_back({"quantise", quantise_});
    if (!opt_.measuring()) return;
    r_->final_error = r_->level_error.at(0);
    r_->timings.push_back({"measure quantised", measure_});
  }

 private:
  const Profile& profile_;
  const PipelineOptions& opt_;
  PipelineResult* r_;
  std::vector<LevelPlanes> levels_;
  Texture coverage_;
  double all_, done_ = 0;
  uint32_t side_w0_ = 0, side_h0_ = 0;  // level 0's low-res direction and ratio planes (dir_ratio_scale > 1)
  double decide_ = 0, quantise_ = 0, measure_ = 0;
};

double chain_texels(int width, int height, int levels) {
  double n = 0;
  for (int l = 0; l < levels; ++l) n += double(mip_size(width, l)) * double(mip_size(height, l));
  return n;
}

}  // namespace

std::vector<FittedLevel> fit_levels(ShImage&& input, const PipelineOptions& opt, PipelineResult* r) {
  opt.step("fit", 0);
  auto t0 = Clock::now();
  std::vector<FitStats> fit_stats;
  std::vector<FittedLevel> levels =
      fit_mip_chain(std::move(input), opt.fit, opt.max_levels, opt.threads, &fit_stats, &r->dilate_stats);
  r->fit_stats = fit_stats[0];
  r->coeffs = levels[0].sh.coeffs;
  r->l1 = measure_l1(levels[0].sh);
  r->warnings = sh_input_warnings(r->l1, r->fit_stats, r->coeffs);
  r->timings.push_back({"mips, fit, dilate", seconds_since(t0)});
  opt.step("fit", 1);
  if (!opt.measuring()) return levels;
  t0 = Clock::now();
  measure_fit(levels[0], opt, r);
  r->timings.push_back({"measure fit", seconds_since(t0)});
  return levels;
}

void quantise_levels(const std::vector<FittedLevel>& levels, const Profile& profile, const PipelineOptions& opt,
                     PipelineResult* r) {
  check_profile(profile, opt);
  double texels = 0;
  for (const FittedLevel& l : levels) texels += double(l.sh.texels());
  ChainEncoder chain(profile, opt, r, texels);
  for (const FittedLevel& l : levels) chain.add(l);
  chain.finish();
}

void PipelineOptions::step(const char* stage, double fraction) const {
  if (cancel && cancel->load(std::memory_order_relaxed)) throw Cancelled();
  if (progress) progress(stage, fraction);
}

PipelineResult run_conversion(const ShImage& sh, const Profile& profile, const PipelineOptions& opt) {
  return run_conversion(ShImage(sh), profile, opt);
}

PipelineResult run_conversion(ShImage&& sh, const Profile& profile, const PipelineOptions& opt) {
  check_profile(profile, opt);
  PipelineResult r;
  const int levels = chain_level_count(sh.width, sh.height, opt.max_levels);
  ChainEncoder chain(profile, opt, &r, chain_texels(sh.width, sh.height, levels));
  double fit = 0, measure = 0;
  ShImage next = std::move(sh);
  for (int l = 0; l < levels; ++l) {
    if (l == 0) opt.step("fit", 0);
    auto t0 = Clock::now();
    FitStats fs;
    DilateStats ds;
    // L0 images (plain lightmaps) store no fit: it is the pure ambient lobe at every texel,
    // computed from the SH where needed (29 bytes a texel, more than twice their SH). The fit's
    // counts are reported for level 0 only: the other levels are not counted (for an L0 image
    // that is a pass over the level that nothing reads).
    FitStats* level_fs = l == 0 ? &fs : nullptr;
    FittedLevel level = next.coeffs == 1 ? fit_ambient_level(std::move(next), opt.fit, opt.threads, level_fs, &ds)
                                         : fit_level(std::move(next), opt.fit, opt.threads, level_fs, &ds);
    r.dilate_stats.push_back(ds);
    fit += seconds_since(t0);
    if (l == 0) {
      r.fit_stats = fs;
      r.coeffs = level.sh.coeffs;
      r.l1 = measure_l1(level.sh);
      r.warnings = sh_input_warnings(r.l1, r.fit_stats, r.coeffs);
      opt.step("fit", 1);
      t0 = Clock::now();
      if (opt.measuring()) measure_fit(level, opt, &r);
      measure = seconds_since(t0);
    }
    chain.add(level);
    level.ahd = AhdImage();  // the fit is done with before the next level is filtered
    t0 = Clock::now();
    if (l + 1 < levels) next = downsample_sh(level.sh, opt.threads);
    fit += seconds_since(t0);
  }
  r.timings.push_back({"mips, fit, dilate", fit});
  if (opt.measuring()) r.timings.push_back({"measure fit", measure});
  chain.finish();
  return r;
}

}  // namespace ahd
