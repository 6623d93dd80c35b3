// BC5 (RGTC2, UNORM): two channels, each a BC4 block (red first, then green), 16 bytes per 4×4.
#pragma once
#include <cstdint>
#include <vector>

#include "core/image.h"

namespace ahd {

// Decodes to floats in [0,1] (exact spec values), out[i*2+c].
void bc5_decode_block(const uint8_t block[16], float out[32]);

// Channels 0 and 1 of img (values in [0,1]); partial edge blocks replicate the edge texels.
// Returns ceil(w/4)·ceil(h/4)·16 bytes, blocks row-major. Deterministic for any thread count.
std::vector<uint8_t> bc5_encode_image(const ImageF& img, int threads, int effort = 1);

// Decodes w×h texels into a 2-channel image.
ImageF bc5_decode_image(const uint8_t* blocks, int width, int height);

}  // namespace ahd
