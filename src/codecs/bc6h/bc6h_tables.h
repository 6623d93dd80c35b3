// BC6H format tables (facts of the specification), shared by the decoder and the encoder.
#pragma once
#include <cstdint>

namespace ahd::bc6h {

// Endpoint fields, in the order the spec names them: w/x are region 0's endpoints, y/z region 1's.
enum Field : uint8_t { RW, GW, BW, RX, GX, BX, RY, GY, BY, RZ, GZ, BZ, D, NONE };

struct ModeInfo {
  uint8_t code;        // mode bits (2 bits for modes 1–2, else 5)
  uint8_t regions;     // 1 or 2
  bool transformed;    // endpoints 1..3 stored as deltas from endpoint 0
  uint8_t index_bits;  // 3 (two regions) or 4 (one region)
  uint8_t epb;         // endpoint precision (bits of w)
  uint8_t delta[3];    // bits of the other endpoints, per channel R, G, B
  // The header's bit layout after the mode bits: (field, bit) per position.
  uint8_t layout_count;
  uint8_t layout_field[80];  // 80 for the 2-bit modes, 77 or 60 for the others
  uint8_t layout_bit[80];
};

constexpr int kModeCount = 14;
struct ModeTable {
  ModeInfo m[kModeCount];
};
extern const ModeTable kModeTable;      // parsed from the spec's layouts at compile time
inline const ModeInfo& mode(int m) { return kModeTable.m[m]; }  // m in [0, 14)
int mode_from_code(uint32_t code);      // −1 for reserved codes

extern const uint16_t kPartitions[32];  // bit t set = texel t in region 1
extern const uint8_t kAnchor2[32];      // index of region 1's anchor texel
extern const uint8_t kWeights3[8];
extern const uint8_t kWeights4[16];

}  // namespace ahd::bc6h

namespace ahd::bc6h {

inline int sign_extend(int v, int bits) {
  const int m = 1 << (bits - 1);
  v &= (1 << bits) - 1;
  return (v ^ m) - m;
}

// Endpoint component (bits wide) → the 16-bit interpolation domain (spec "unquantize").
inline int unquantize(int comp, int bits, bool is_signed) {
  if (!is_signed) {
    if (bits >= 15) return comp;
    if (comp == 0) return 0;
    if (comp == (1 << bits) - 1) return 0xFFFF;
    return ((comp << 16) + 0x8000) >> bits;
  }
  if (bits >= 16) return comp;
  const bool neg = comp < 0;
  int c = neg ? -comp : comp;
  int u;
  if (c == 0) u = 0;
  else if (c >= (1 << (bits - 1)) - 1) u = 0x7FFF;
  else u = ((c << 15) + 0x4000) >> (bits - 1);
  return neg ? -u : u;
}

inline int interpolate(int a, int b, int w) { return (a * (64 - w) + b * w + 32) >> 6; }

// Interpolated 16-bit value → half-float bits (spec "finish unquantize").
inline uint16_t finish_unquantize(int c, bool is_signed) {
  if (!is_signed) return uint16_t((c * 31) >> 6);
  if (c < 0) return uint16_t(0x8000 | ((-c * 31) >> 5));
  return uint16_t((c * 31) >> 5);
}

}  // namespace ahd::bc6h
