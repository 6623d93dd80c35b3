// The two-region candidate of `fast` (bc6h_fast_two_region.cpp): what its scalar steps and its
// AVX-512 steps (bc6h_two_region_avx512.cpp) share. Internal to the codec.
#pragma once
#include <cstdint>

namespace ahd::bc6h::two_region {

constexpr int kW3[8] = {0, 9, 18, 27, 37, 46, 55, 64};  // kWeights3, usable in constant expressions

// A component's 16-bit interpolation value (bits wide, unsigned), and an interpolation value's
// half bits.
inline int unq(int e, int bits) {
  if (e == 0) return 0;
  if (e == (1 << bits) - 1) return 0xFFFF;
  return ((e << 16) + 0x8000) >> bits;
}
inline int dec(int c) { return (c * 31) >> 6; }

// A block's texels as channel planes: half bits H, the metric's weights W per channel and tw
// averaged, each channel's no-specks cap, and which texels are real.
struct Planes {
  float H[3][16], W[3][16], tw[16];
  int cap[3];
  uint8_t valid[16];
};

// Partitions the AVX-512 steps take at once: one (partition, region) per lane.
constexpr int kAvx512Partitions = 8;

// assign_region for both regions at once, the sixteen texels in one AVX-512 register: err[r] and
// idx bit for bit assign_region's for region r (endpoints e[2r], e[2r + 1]). Call only when
// cpu::has(cpu::kAvx512).
void assign_both_avx512(const Planes& f, uint16_t mask, const int e[4][3], int bits, uint8_t idx[16], float err[2]);

// axis_targets for both regions of kAvx512Partitions partitions (kPartitions[parts[i]]) at once:
// targets[i][r] = {a, b} bit for bit axis_targets'. Call only when cpu::has(cpu::kAvx512).
void axis_targets_avx512(const Planes& f, const int parts[kAvx512Partitions],
                         float targets[kAvx512Partitions][2][2][3]);

}  // namespace ahd::bc6h::two_region
