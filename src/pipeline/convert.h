// SH lightmap → fitted AHD → quantised planes (closed loop) → textures, with per-stage cost and
// error. A pure function: no file I/O (the CLI reads inputs and writes what this returns).
#pragma once
#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "core/texture.h"
#include "fit/fit_image.h"
#include "fit/hemisphere_error.h"
#include "mips/dilate.h"
#include "pipeline/plane_codec.h"
#include "pipeline/plane_decode.h"
#include "pipeline/profile.h"
#include "pipeline/sh_input_check.h"
#include "sh/sh_image.h"

namespace ahd {

// Whether the direction and ratio planes are written. A lightmap whose lighting barely depends on
// the normal (a plain lightmap, or SH with a negligible L1/L2 part) needs only I_z: Auto drops the
// other planes when decoding I_z alone (d = z, ratio = 1: I(n) = I_z) stays within
// `ambient_threshold` of the SH — relative hemisphere RMSE p99 over covered texels of level 0.
// The default 1 % is where dropping them costs less than the 8-bit direction/ratio planes' own
// quantisation error (measured by `ahdpack report direction`; docs/container-format.md "Outputs").
constexpr double kDefaultAmbientThreshold = 0.01;

// Every default is ConversionOptions' (<ahd/convert.h>; test OptionTable.InternalDefaultsAreThePublicOnes),
// so a conversion run below the API (the report commands, the tests) runs what ahd::convert runs.
struct PipelineOptions {
  // The conversion's fit: the refined direction fit, not FitOptions' own default (the paper's linear
  // fit, what the fit stage's tests take alone).
  FitOptions fit = {.direction_fit = DirectionFit::Refined};
  bool closed_loop = true;
  // Off: no error measurement (the library's default: a cook step pays only for the conversion).
  // Estimate: a deterministic sample of texels per level. Full: every texel and level, plus the
  // unconstrained LS and open-loop baselines (the report commands).
  Measure measure = Measure::Off;
  PlaneCodecOptions codec;  // its `threads` is ignored: `threads` below is the one thread count
  int threads = 0;          // 0 = all hardware threads; the bytes never depend on it
  int max_levels = 0;  // mip levels to write: 0 = the full chain down to 1×1
  bool coverage_plane = false;  // also write an R8 "coverage" plane (255 = covered) per level
  DirectionPlanes direction = DirectionPlanes::Auto;
  double ambient_threshold = kDefaultAmbientThreshold;
  // Called from the calling thread between steps: stage name and fraction done in [0, 1].
  std::function<void(const char* stage, double fraction)> progress;
  // When set and raised (by any thread), the conversion stops at its next step with ahd::Cancelled.
  const std::atomic<bool>* cancel = nullptr;

  // With Measure::Full: also the unconstrained-LS and open-loop baselines (off saves the report
  // commands' time where they print neither).
  bool measure_baselines = true;

  bool measuring() const { return measure != Measure::Off; }
  bool measuring_baselines() const { return measure == Measure::Full && measure_baselines; }
  // Reports progress and honours the cancel flag (throws ahd::Cancelled).
  void step(const char* stage, double fraction) const;
};

struct StageCost {
  std::string stage;
  double seconds = 0;
};

struct PipelineResult {
  std::vector<Plane> planes;
  FitStats fit_stats;                   // level 0
  std::vector<DilateStats> dilate_stats;  // per level: guard texels, rings
  ErrorReport fit_error;            // the fitted AHD (before quantisation) vs the SH
  ErrorReport unconstrained_error;  // the unconstrained LS fit with the same d, vs the SH
  ErrorReport open_loop_error;      // quantised, ratio from the unquantised fit
  ErrorReport final_error;          // quantised, what the files decode to, vs the SH (level 0)
  std::vector<ErrorReport> level_error;  // the same for every mip level, vs that level's SH
  PlaneCodecStats codec_stats;
  std::vector<StageCost> timings;
  bool directional = true;    // the direction and ratio planes were written
  ErrorReport ambient_error;  // I_z alone (d = z, ratio = 1) vs the SH, level 0 (Auto, when measuring)
  std::string direction_reason;  // why the planes were kept or dropped (for the report)
  int coeffs = 0;                // the input's SH coefficients (1: no L1)
  L1Figures l1;                  // the input's L1 signs and zeros, level 0 (pipeline/sh_input_check.h)
  std::vector<std::string> warnings;  // bad or unsuitable data, one sentence each (sh_input_warnings)
  // An atlas (pipeline/pages.h): each page's own figures, planes left out; the fields above are
  // then every page's totals. Empty for one page.
  std::vector<PipelineResult> pages;
};

// Throws ahd::Error when `profile` cannot be written with these options (a format this build cannot
// encode, the RGB ratio form with a one-channel ratio plane).
void check_profile(const Profile& profile, const PipelineOptions& opt);

// The whole conversion: the same bytes and figures as fit_levels then quantise_levels, but level by
// level — each level is fitted, quantised and measured, and only its SH is kept to filter the next
// — so the peak memory is level 0's SH and fit plus one level's encoder temporaries, not the chain's.
// Progress: "fit" (level 0), then "encode" (level 0's planes, then the smaller levels, each fitted
// and encoded in turn). The by-value overload takes the input over (no copy of level 0).
PipelineResult run_conversion(const ShImage& sh, const Profile& profile, const PipelineOptions& opt);
PipelineResult run_conversion(ShImage&& sh, const Profile& profile, const PipelineOptions& opt);

// Fit stage: the SH mip chain, the AHD fit of every level, dilation of uncovered texels.
// Fills r->fit_stats, r->fit_error and r->unconstrained_error (level 0) and timings.
std::vector<FittedLevel> fit_levels(const ShImage& sh, const PipelineOptions& opt, PipelineResult* r);
// The same, taking the input over (it becomes level 0): no copy of the largest image. Callers
// that no longer need their ShImage pass std::move(sh).
std::vector<FittedLevel> fit_levels(ShImage&& sh, const PipelineOptions& opt, PipelineResult* r);

// Quantise stage: planes of every level for the profile (closed loop per level), measured against
// each level's SH. Also what `transcode` runs on a stored intermediate.
void quantise_levels(const std::vector<FittedLevel>& levels, const Profile& profile, const PipelineOptions& opt,
                     PipelineResult* r);

// What decoding I_z alone (d = z, ratio = 1) gives, per texel, and its error against the level's SH.
std::vector<AhdLobe> ambient_only_lobes(const FittedLevel& level);
ErrorReport ambient_only_error(const FittedLevel& level, int threads);

}  // namespace ahd
