// The tool's canonical SH lightmap file: one multi-channel float EXR.
//   channels sh0.R sh0.G sh0.B … sh3.B (L1) or … sh8.B (L2), canonical order and normalisation
//   (sh/sh.h), tangent space; optional `coverage` (> 0.5 = covered); optional `normal.X/Y/Z`
//   (then the SH is in WORLD space and these are the texels' unit geometric normals).
#pragma once
#include <cstddef>
#include <string>

#include "sh/sh_image.h"

namespace ahd {

// What reading had to fix, counted (never silent).
struct ReadStats {
  size_t non_finite_texels = 0;   // NaN/Inf in any coefficient: texel zeroed and marked uncovered
  bool coverage_derived = false;  // no coverage channel: all-zero SH = uncovered
  // The colour space the input was converted from (image/colour_space.h SourceSpace::describe), ""
  // when it was read in the working space untouched.
  std::string input_space;
};

// Reads and validates the canonical EXR. Throws ahd::Error("<path>: <cause>") for a missing file,
// a missing or extra sh channel, a non-float file, bad normals, a colour space that cannot be
// converted. Its SH is converted to the working space from `input_space` (a --input-space name,
// image/colour_space.h) or, when that is empty, from the space the file declares.
ShImage read_canonical_sh(const std::string& path, ReadStats* stats = nullptr, const std::string& input_space = "");

// Writes the canonical EXR (float channels; with coverage, and normals when present). Atomic.
void write_canonical_sh(const std::string& path, const ShImage& img);

// Applies the read-time rules (non-finite → zero + uncovered; derived coverage) in place.
void sanitise_sh(ShImage& img, bool derive_coverage, ReadStats* stats);

// Coefficients beyond this magnitude count as non-finite in sanitise_sh: no radiance is near it,
// and the fit's squares of such values overflow (3e38 everywhere fitted to a black map).
constexpr float kMaxShMagnitude = 1e18f;

// The one rule of every SH reader (canonical EXR and baker layouts alike): when sanitise_sh found
// non-finite texels (`non_finite` of them) and no covered texel is left, the file is a NaN/Inf
// flood, not a lightmap to convert to black. Throws ahd::Error("<path>: no finite texel …").
void check_not_flooded(const std::string& path, const ShImage& img, size_t non_finite);

}  // namespace ahd
