// BC6H (BPTC float): HDR RGB, 4×4 texels in 16 bytes, unsigned (UF16) and signed (SF16).
// Written from the Khronos Data Format Specification (BPTC) and the D3D11 functional spec: 14
// modes (10 with two regions over 32 partitions and 3-bit indices, 4 with one region and 4-bit
// indices), endpoint deltas, unquantisation and the final scale to half floats.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <ahd/types.h>

#include "core/image.h"

namespace ahd {

// Decodes one block to 16 RGB half-float bit patterns (out[i*3+c]). Reserved modes decode to 0.
// Safe on any 16 bytes.
void bc6h_decode_block(const uint8_t block[16], bool is_signed, uint16_t out_half_rgb[48]);

// Decodes texel t (0..15, row-major in the block) of one block: out = bc6h_decode_block's
// out[t*3 .. t*3+3), without the other fifteen (the error estimate decodes one texel a block).
// Safe on any 16 bytes; t outside 0..15 is the caller's error.
void bc6h_decode_texel(const uint8_t block[16], bool is_signed, int t, uint16_t out_half_rgb[3]);

// Quality levels of the encoder: which candidates it tries (see bc6h_encoder.cpp).
bool bc6h_quality_from_name(const std::string& name, Bc6hQuality* out);
const char* bc6h_quality_name(Bc6hQuality q);

struct Bc6hOptions {
  bool is_signed = false;
  Bc6hQuality quality = Bc6hQuality::Default;
  int threads = 0;  // 0 = all hardware threads
};

// What the encoder had to change in its input (counted, never silent). The rule: NaN → 0;
// +Inf and values above the largest finite half (65504) → 65504 (−65504 for −Inf/below in SF16);
// UF16 cannot hold negatives → 0.
struct Bc6hStats {
  size_t nan = 0;
  size_t inf = 0;
  size_t too_large = 0;
  size_t negative = 0;  // UF16 only
};

// Encodes the first three channels of `img` (any size ≥ 1×1). Partial edge blocks are padded by
// repeating the edge texels; padded texels do not count in the encoder's error. Returns
// ceil(w/4)·ceil(h/4)·16 bytes, blocks row-major. The bytes of a block depend only on its own
// texels: identical whatever the thread count or the neighbours.
std::vector<uint8_t> bc6h_encode_image(const ImageF& img, const Bc6hOptions& opt, Bc6hStats* stats = nullptr);

// Decodes w×h texels to a 3-channel float image.
ImageF bc6h_decode_image(const uint8_t* blocks, int width, int height, bool is_signed);

// Encodes one block of 16 RGB floats (any values: the input rule above is applied, uncounted);
// the same bytes as that block within bc6h_encode_image.
void bc6h_encode_block(const float rgb[48], const uint8_t valid[16], bool is_signed, Bc6hQuality q, uint8_t out[16]);

}  // namespace ahd
