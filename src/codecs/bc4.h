// BC4 (RGTC1, UNORM): one channel, 4×4 texels in 8 bytes. Written from the Khronos Data Format
// Specification (RGTC section): two 8-bit endpoints r0, r1 and 16 3-bit indices; r0 > r1 selects
// 8 interpolated values, r0 ≤ r1 selects 6 interpolated values plus 0 and 1.
#pragma once
#include <cstdint>
#include <vector>

#include "core/image.h"

namespace ahd {

// Exact palette values of a block, in [0,1], as the specification defines them.
void bc4_palette(uint8_t r0, uint8_t r1, float palette[8]);


// Decodes to floats in [0,1] (exact spec values). Safe on any 8 bytes.
void bc4_decode_block(const uint8_t block[8], float out[16]);

// Decodes to 8 bits with the fixed-point interpolation of Mesa's llvmpipe (weights 255·64/7 and
// 255·64/5 per index step, 16-bit lanes): within one step of the exact palette. Used to compare
// our bit parsing and mode selection with Mesa bit for bit; the pipeline uses the exact decode.
void bc4_decode_block_unorm8(const uint8_t block[8], uint8_t out[16]);

// Encodes 16 values in [0,1] (row-major 4×4; out-of-range values are clamped). Tries both modes
// and a local search around the range endpoints; error measured against the exact palette.
// `effort` 0 = fast (endpoints from the range), 1 = default (±2 search), 2 = high (±4 search).
void bc4_encode_block(const float texels[16], uint8_t out[8], int effort = 1);

// Whole images: channel `channel` of img (values in [0,1]); partial edge blocks replicate the
// edge texels. Returns ceil(w/4)·ceil(h/4)·8 bytes, blocks row-major. Deterministic for any
// thread count.
std::vector<uint8_t> bc4_encode_image(const ImageF& img, int channel, int threads, int effort = 1);

// Decodes w×h texels (one channel, exact spec values) from blocks of bc4_encode_image's layout,
// reading 8-byte blocks at `stride` bytes (8 for BC4, 16 for one half of BC5) from `offset`.
void bc4_decode_image(const uint8_t* blocks, int width, int height, int stride, int offset, ImageF& out, int channel);

}  // namespace ahd
