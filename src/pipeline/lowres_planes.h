// The direction and ratio planes of one level at a fraction of its resolution (a profile's
// "dir_ratio_scale", issue 43; the fit is fit/lowres_fit.h). I_z is coded first at full resolution;
// the low-res planes are then fitted against what the decoder will see at every full-res texel:
// its own decoded I_z and the bilinearly sampled low-res direction and ratio.
#pragma once
#include "core/texture.h"
#include "pipeline/convert.h"

namespace ahd {

// Projected Gauss–Seidel sweeps on the low-res ratio after its box least-squares start
// (fit/lowres_fit.h lowres_ratio_sweeps).
constexpr int kLowResRatioSweeps = 4;
// Pattern-search sweeps on the low-res direction before it is coded (fit/lowres_fit.h
// lowres_direction_sweeps); 0 keeps the box fit's direction.
constexpr int kLowResDirectionSweeps = 3;

struct LowResPlanes {
  TextureLevel dir, ratio, dirratio;  // dir + ratio, or dirratio when the profile packs them
};

// The lw×lh side planes of level `lv` whose I_z plane was coded as `iz` (profile.iz). Uncovered
// low-res texels (no covered texel in their box) are dilated. Deterministic at any thread count.
// (Like the full-resolution side planes, these count nothing into the codec statistics.)
LowResPlanes lowres_level_planes(const FittedLevel& lv, const TextureLevel& iz, const Profile& profile,
                                 const PipelineOptions& opt, int lw, int lh);

}  // namespace ahd
