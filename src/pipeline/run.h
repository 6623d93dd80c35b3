// The whole conversion as one call, for the CLI and the public API alike: fit → quantise → package,
// with per-stage seconds. Everything a caller does around it is reading inputs and publishing files.
#pragma once
#include <functional>
#include <vector>

#include "pipeline/convert.h"
#include "pipeline/package.h"

namespace ahd {

struct ConversionRun {
  PipelineResult result;      // planes, statistics, errors (as measured), timings
  PackagedConversion output;  // the files, manifest first-class
  double seconds = 0;         // total, including the `prior` stages the caller timed
};

// SH → files. The SH is first scaled by pkg.iz_scale (stored I_z = iz_scale × E). `sh` is taken by value: move the input in and it becomes mip level 0 without a copy
// (a 4096² L2 image is 1.8 GB). `prior` are stages the caller already timed (e.g. reading the input); they lead the
// report's timings and count in its total. `on_fitted` (optional) sees the fitted levels before
// quantisation (the CLI writes the lossless intermediate there).
ConversionRun run_conversion(ShImage sh, const Profile& profile, const PipelineOptions& opt,
                             const PackageOptions& pkg, std::vector<StageCost> prior = {},
                             const std::function<void(const std::vector<FittedLevel>&)>& on_fitted = {});

// The pages of an atlas → files whose planes are array textures, layer p = page p
// (pipeline/pages.h: every layer equals that page converted alone).
ConversionRun run_pages(std::vector<ShImage> pages, const Profile& profile, const PipelineOptions& opt,
                        const PackageOptions& pkg, std::vector<StageCost> prior = {});

// Fitted levels (a stored intermediate) → files: quantise and package only.
ConversionRun run_transcode(const std::vector<FittedLevel>& levels, const Profile& profile, const PipelineOptions& opt,
                            const PackageOptions& pkg, std::vector<StageCost> prior = {});

}  // namespace ahd
