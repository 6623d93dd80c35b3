// The searched encoder's index step (bc6h_encoder.cpp's evaluate) with AVX-512. Internal to the
// codec.
#pragma once
#include <cstdint>

namespace ahd::bc6h {

// pick_indices_avx2 (bc6h_search_avx2.h) with sixteen texels per AVX-512 vector: the same
// indices and error. Call only when cpu::has(cpu::kAvx512).
double pick_indices_avx512(const float target[3][16], const float valid[16], const float pal[2][3][16], uint16_t mask,
                           int n, float off, uint8_t idx[16]);

}  // namespace ahd::bc6h
