// The bakers' own directional formats at their real bytes, for `report truth` (issue 27's
// "representations at equal bytes"): each built from the same L1 part of the baker's SH, stored
// through our real codecs as the engine would load it, and decoded with the baker's runtime formula
// (docs/bakers.md). Lab code.
#pragma once
#include <string>
#include <vector>

#include "lab/truth_reference.h"
#include "sh/sh_image.h"

namespace ahd {

struct BakerFormatEval {
  TruthEval eval;             // irradiance E for texel i at tangent-space normal n (captures its data)
  double bytes_per_texel = 0; // level 0 as the engine loads it; 0 = float, not a shipped format
  std::string label;          // the row's name in `report truth` (the baker and the storage)
};

// Bakery's MonoSH: L0 RGB and one L1 vector shared by the channels, the luminance's L1 over its L0,
// stored t = L1/(4·L0) + 0.5. Decoded E_c(n) = max(0, L0_c + (2t − 1)·2·L0_c · n). Quantised: L0 in
// BC6H (unsigned, default quality), t in RGBA8 (5 bytes a texel); otherwise both float.
// `sh` must hold 4 or 9 coefficients (only the L1 part is used).
BakerFormatEval mono_sh_format(const ShImage& sh, bool quantised);

// Godot 4's directional LightmapGI (packed, 4.2+): L0 RGB and per axis an RGB layer
// t = L1/(8·L0) + 0.5, clamped to [0, 1]. Decoded E_c(n) = max(0, L0_c + 8·(t − 0.5)·L0_c · n).
// Quantised: the four layers in BC6H (unsigned, default quality; Godot's VRAM-compressed import,
// 4 bytes a texel); otherwise float.
BakerFormatEval godot_l1_format(const ShImage& sh, bool quantised);

// Godot's LDR directional lightmap (PR #100790, open; after Frostbite's GDC 2018 "Precomputed
// Global Illumination in Frostbite"): L0 RGB stays an HDR layer (BC6H, 1 byte a texel) and one
// direction texture, the luminance's L1 over the luminance's L0, is saved as an 8-bit PNG and
// imported as BC1/DXT1 RGB (0.5 bytes a texel): t = Y(L1)/(8·Y(L0)) + 0.5 clamped to [0, 1],
// decoded like Godot's packed L1 with t shared by the channels, E_c(n) = max(0, L0_c + 8·(t − 0.5)·L0_c · n).
// `dir_scale` 2 is PR #108405's directional texture at half the lightmap's resolution
// (0.5 / 4 bytes a texel; baked over each 2×2 footprint, sampled bilinearly, clamp to edge).
// Quantised: L0 in BC6H, t in 8 bits then BC1 (our encoder, codecs/bc1.h); otherwise float
// (at dir_scale 1 the float format is MonoSH's: one shared L1, a different constant).
BakerFormatEval godot_ldr_format(const ShImage& sh, bool quantised, int dir_scale);

// Unity's Directional mode, which is Enlighten's "directional irradiance" (one dominant direction
// for all channels): a lightmap C (the irradiance along the surface normal, as a non-directional
// lightmap holds it) and an RGBA texture (v·0.5 + 0.5, w), decoded by Unity's
// DecodeDirectionalLightmap: E_c(n) = C_c · (dot(n, rgb − 0.5) + 0.5) / max(1e-4, w).
// v is the luminance's L1 over its L0 (|v| clamped to 1: the half-Lambert can hold no more), w the
// same half-Lambert at the baking normal, so n = normal gives C back. Quantised: C in BC6H
// (1 byte), the direction texture in RGBA8 standing in for Unity's BC7 (1 byte a texel too; 8
// bits a channel is at least as good as BC7, so this favours the anchor); otherwise float.
BakerFormatEval unity_directional_format(const ShImage& sh, bool quantised);

// A plain (non-directional) lightmap: the irradiance along the surface normal, max(0, I_z), in
// BC6H (unsigned, default quality), 1 byte a texel, the same at every normal.
BakerFormatEval plain_bc6h_format(const ShImage& sh);

// The bakers' own directional formats above, in the order `report truth` lists them: quantised,
// every format at its shipped bytes; float, the ones whose float form differs from the others'.
std::vector<BakerFormatEval> baker_formats(const ShImage& sh, bool quantised);

}  // namespace ahd
