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

// Godot's LDR directional lightmap (godotengine/godot PR #100790, open; its description: the
// directional data leave the HDR lightmap array for a separate 8-bit "_directional.png" imported as
// DXT1/ETC2 RGB, after Frostbite's GDC 2018 "Precomputed Global Illumination in Frostbite"): L0 RGB
// stays an HDR layer (BC6H, 1 byte a texel) and one direction texture, the luminance's L1 over the
// luminance's L0, becomes BC1 (0.5 bytes a texel). The PR's shader was not readable here: t is
// modelled on Godot's packed L1 (PR #96114; scene_forward_mobile.glsl multiplies (t − 0.5)·2 by
// L0·4), t = Y(L1)/(8·Y(L0)) + 0.5 clamped to [0, 1], decoded with t shared by the channels,
// E_c(n) = max(0, L0_c + 8·(t − 0.5)·L0_c · n); the constant's effect is measured in
// docs/accuracy-real-lighting.md "The engine anchors, and where their facts come from".
// `dir_scale` 2 is PR #108405's directional texture at half the lightmap's resolution (its
// `directional_scale_ratio` 0.5: 0.5 / 4 bytes a texel; baked over each 2×2 footprint, dilated,
// sampled bilinearly at the lightmap's texel centres, clamp to edge).
// Quantised: L0 in BC6H, t in 8 bits then BC1 (our encoder, codecs/bc1.h); otherwise float
// (at dir_scale 1 the float format is MonoSH's: one shared L1, a different constant).
BakerFormatEval godot_ldr_format(const ShImage& sh, bool quantised, int dir_scale);

// Unity's Directional mode, which is Enlighten's "directional irradiance" (one dominant direction
// for all channels): a lightmap C (the irradiance along the surface normal, as a non-directional
// lightmap holds it) and an RGBA texture (v·0.5 + 0.5, w), decoded by Unity's
// DecodeDirectionalLightmap (UnityCG.cginc): E_c(n) = C_c · (dot(n, rgb − 0.5) + 0.5) / max(1e-4, w).
// Sources: Unity's manual "Lightmap Directional Modes" (2018.x: baked by Enlighten; the second map
// holds the dominant direction and a factor for how much light comes along it, the rest uniform);
// TheRealMJP/BakingLab PR #10 (Enlighten's format after the Enlighten 3.08 SDK documentation: the
// same decode, w = the half-Lambert at the baking normal). From L1 SH: v = Y(L1)/Y(L0), the
// luminance's irradiance gradient over its mean (|v| clamped to 1, the most the half-Lambert holds;
// BakingLab's baker always normalises it), w = (1 + v_z)/2, so n = normal gives C back. Quantised: C in BC6H
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
