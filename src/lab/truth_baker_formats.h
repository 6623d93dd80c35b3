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

// The bakers' own directional formats above, in the order `report truth` lists them.
std::vector<BakerFormatEval> baker_formats(const ShImage& sh, bool quantised);

}  // namespace ahd
