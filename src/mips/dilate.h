// Dilation: values for the texels no chart covers, so that bilinear filtering, mips and 4×4 block
// codecs never pull garbage into a chart.
//
// Rule (iterative flood fill, Jacobi rings): ring 0 = the covered texels (never changed). Ring r+1 =
// the uncovered texels with at least one 8-neighbour in rings ≤ r; each takes the weighted mean of
// those neighbours only (edge neighbours weight 2, corner neighbours weight 1: closer texels count
// more), all of ring r+1 computed from the state after ring r. Hence:
// - the result is a function of the covered texels alone (garbage in uncovered texels never
//   survives), and independent of the thread count and visiting order;
// - every value is a convex combination of covered values (no overshoot: I_z stays ≥ 0, ratios in
//   [0,1]);
// - the rings stop at kDilateRings: a texel farther than that from every covered texel is set to 0
//   (dilate_ahd: black, d = z, ratio 1). Nothing samples it: bilinear taps around a covered texel
//   reach ring 1, and every 4×4 block holding a ring-1 texel lies within ring 4, so each block a
//   sampler can touch decodes exactly as with rings to the image's edge (the mips are
//   coverage-weighted and never read uncovered texels). Issue 28: a Godot bake's gutters took 944
//   rings, 30 % of a plain map's conversion; an image with no covered texel is filled with 0;
// - ring 1 (the guard band, one texel around each chart) sees only its own chart when the gutter
//   between two charts is ≥ 2 texels wide: no bleeding across gutters at the level where they exist.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/image.h"
#include "fit/fit_image.h"

namespace ahd {

// Rings filled around the coverage (twice the four that sampled blocks need: room for wide
// anisotropic footprints).
constexpr int kDilateRings = 8;

struct DilateStats {
  size_t covered = 0;  // texels left as they were
  size_t guard = 0;    // ring-1 texels: uncovered, 8-adjacent to a covered texel
  size_t filled = 0;   // all uncovered texels given a value (= texels - covered)
  int rings = 0;       // flood-fill rings filled (at most kDilateRings)
  size_t far = 0;      // uncovered texels beyond the rings, set to 0
};

// Dilates every channel of `plane` in place. coverage: width*height bytes, nonzero = covered.
// Throws ahd::Error when the sizes disagree.
void dilate(ImageF& plane, const std::vector<uint8_t>& coverage, int threads, DilateStats* stats = nullptr);

// Dilates a fitted image in place (uncovered texels only): I_z, d and ratio are filled by dilate();
// d is filled as a 3-vector and renormalised (the mean of unit vectors with d_z ≥ dz_min keeps
// d_z ≥ dz_min after renormalisation; the horizon rule is applied anyway); ca/cd are then derived
// with the reference decoder (decode_colours) so the texel is self-consistent; flags = 0.
// Why the 3-vector and not the stored hemi-octahedral uv: the fit stage does not know the plane
// encoding, and the 3-vector mean is encoding-independent.
void dilate_ahd(AhdImage& img, double dz_min, int threads, DilateStats* stats = nullptr);

// The dilation of an L0 image's fit (fit_image.h, ambient-only levels) without a plane of it: the
// covered texels' I_z are computed from their SH (fit_ambient_texel), and each uncovered texel's
// dilated I_z (as dilate_ahd gives it: filled, then clamped at 0) is written into its own SH slot.
// Throws ahd::Error on a malformed image or one with L1/L2 coefficients.
void dilate_ambient(ShImage& sh, int threads, DilateStats* stats = nullptr);

// The optional coverage plane for engines that want it: R8, 255 = covered, 0 = not.
Image8 coverage_plane(int width, int height, const std::vector<uint8_t>& coverage);

}  // namespace ahd
