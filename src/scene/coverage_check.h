// Never silently wrong: the coverage rasterised from a mesh against what the baker itself wrote.
// A texel is lit when any of its stored SH numbers is non-zero (bakers write exact zeros outside
// their charts) — on an atlas with a fill (fill_background), when it is brighter than the fill in
// L0; a mesh whose lightmap UVs are not the ones the bake used covers the wrong texels.
#pragma once
#include <ahd/types.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ahd {

// Bakers are not exact about their own charts, and a comparison must not call that a mismatch:
// - they dilate every chart into its gutter (Godot 4.2: a ring of up to 3 texels) so that filtering never
//   reads black: lit texels within kDilation texels of the coverage are the baker's ring;
// - a chart's unlit part is stored as exact zeros (a dark corner with no bounce light): a black
//   region of the coverage that touches a lit covered texel (4-connected) is part of a lit chart.
// What is left is the mismatch: lit texels far from any covered texel (light where the mesh puts
// nothing) and covered regions that are black throughout (the mesh where the baker put nothing).
constexpr int kDilation = 3;
// Godot 4.4+ (the packed-L1 bakes): its dilation fills up to 4 · supersampling_factor texels of the
// bake along the 8 axis and diagonal directions (modules/lightmapper_rd/lm_compute.glsl, MODE_DILATE,
// since godotengine/godot#100765: 4 texels of the saved lightmap), and its raster pass draws every
// triangle filled and as lines, shifted half a texel up-left (lightmapper_rd.cpp, uv_offset,
// godotengine/godot#81872), which covers texels up to one beyond a conservative raster: 5 in all
// (measured on tests/data/godot/corpus, docs/godot.md "The corpus").
constexpr int kGodot44Dilation = 5;

struct CoverageComparison {
  size_t covered = 0;          // texels the mesh covers
  size_t lit = 0;              // texels the lightmap holds light in
  size_t both = 0;             // covered and lit
  size_t ring = 0;             // lit, not covered, within `ring` texels of the coverage
  size_t lit_outside = 0;      // lit, farther from the coverage
  size_t dark_in_chart = 0;    // covered, black, in a black region touching lit covered texels
  size_t covered_black = 0;    // covered, black, in a region with no lit texel
  // The atlas background (fill_background below): texels holding it are neither lit nor black.
  size_t fill = 0;             // texels holding the background value (0: no background found)
  size_t covered_fill = 0;     // covered texels holding it: the mesh where the baker put its fill
  // Intersection over union of the mesh's lit charts and the baker's lit charts:
  // (both + dark_in_chart) / (covered − covered_black + lit_outside). Regions black throughout are
  // left out of both sets (the lightmap cannot tell a chart that received no light from empty
  // space) and judged on their own (covered_black). 1 when both are empty.
  double iou = 1;
};

// A baker's flat fill of unused atlas space (Unity fills it with one colour; Bevy's lightmaps hold
// one value there beside zeros and stray garbage): the most frequent non-zero texel value, when it
// holds at least kFillShare of the texels and kFillRatio times as many as the next most frequent
// one. A lit chart is never that uniform: on Bevy's Cornell box lightmaps (B10G11R11, 6-bit
// mantissas) the fill holds 4.2–17 % of the texels and 7.5–35 times the next value (a lit chart's
// most frequent value 0.5–0.7 %). At least kFillShare of the texels must be lit with other values
// (an image of one value throughout has no fill: nothing lit beside it). Returns the number of texels marked in *is_fill (1 = holds it).
constexpr double kFillShare = 0.02;
constexpr double kFillRatio = 4.0;
size_t fill_background(const ShImage& sh, std::vector<uint8_t>* is_fill);

// `covered` holds sh.texels() entries (1 = covered), row-major width × height; `ring`: the
// baker's dilation in texels (Chebyshev distance); `find_fill`: look for the atlas's fill
// (fill_background) — not for Godot, which writes exact zeros outside its charts and whose charts
// may be lit uniformly (tests/data/godot/corpus/gltf: one value on 74 % of the covered texels).
// Pure; cost linear in the texels (× ring²).
CoverageComparison compare_coverage(const std::vector<uint8_t>& covered, const ShImage& sh, int ring = kDilation,
                                    bool find_fill = true);

// one line of the counts and the agreement.
std::string describe_coverage(const CoverageComparison& c);

// Why the coverage is not the lightmap's, or "" when it is: the agreement (iou) below 0.9, more
// than 5 % of the lit texels far outside the coverage, or more than 10 % of the covered texels in
// black regions or holding the atlas's fill (a mesh placed where the baker put nothing: Unity's
// flat-filled atlases, where "lit" would otherwise be every texel). The measured margins are in docs/godot.md (the real Godot 4.2 bake with its own
// meshes, and the same meshes' UV set 0).
std::string coverage_mismatch(const CoverageComparison& c);

}  // namespace ahd
