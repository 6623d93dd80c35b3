// BC1 (S3TC DXT1, RGB, UNORM): 4×4 texels in 8 bytes. Written from the Khronos Data Format
// Specification (S3TC section, "BC1 with no alpha"): two RGB565 endpoints color0, color1 (little
// endian) and 16 2-bit indices (texel i at bits 2i..2i+1, row-major). color0 > color1 (as 16-bit
// integers) selects four colours: c0, c1, (2·c0 + c1)/3, (c0 + 2·c1)/3; otherwise three: c0, c1,
// (c0 + c1)/2 and black. Endpoints expand to [0,1] as r5/31, g6/63, b5/31.
// Used by the lab (`report truth`'s engine anchors: Godot's LDR directional texture); not a
// pipeline output format.
#pragma once
#include <cstdint>
#include <vector>

#include "core/image.h"

namespace ahd {

// The block's four palette colours (RGB in [0,1], exact spec values).
void bc1_palette(uint16_t color0, uint16_t color1, float palette[4][3]);

// Decodes to floats in [0,1] (exact spec values), 16 texels × RGB. Safe on any 8 bytes.
void bc1_decode_block(const uint8_t block[8], float out[16 * 3]);

// Decodes to 8 bits with the integer arithmetic of a software decoder: endpoints widened by bit
// replication, the three-colour midpoint (a + b + 1)/2, the four-colour thirds (2·a + b)/3
// truncated; within 1.37 8-bit steps of the exact palette (every endpoint pair). Mesa's llvmpipe
// returns exactly these values except for the four-colour thirds, which it rounds its own way
// (within one step of these; tests/judges/gl/bc1_mesa_test.cpp). The lab uses the exact decode.
void bc1_decode_block_unorm8(const uint8_t block[8], uint8_t out[16 * 3]);

// Encodes 16 RGB texels in [0,1] (row-major 4×4, 3 floats each; out-of-range values are clamped)
// in four-colour mode: endpoints on the colours' principal axis (their extreme projections), then
// least-squares refits of the endpoints to the chosen indices, keeping the lowest squared error
// measured on the exact palette. Deterministic.
void bc1_encode_block(const float texels[16 * 3], uint8_t out[8]);

// Whole images: channels 0..2 of img (values in [0,1]); partial edge blocks replicate the edge
// texels. Returns ceil(w/4)·ceil(h/4)·8 bytes, blocks row-major. Deterministic.
std::vector<uint8_t> bc1_encode_image(const ImageF& img);

// Decodes w×h RGB texels (exact spec values) from blocks of bc1_encode_image's layout.
// `blocks` must hold ceil(w/4)·ceil(h/4)·8 bytes.
ImageF bc1_decode_image(const uint8_t* blocks, int width, int height);

}  // namespace ahd
