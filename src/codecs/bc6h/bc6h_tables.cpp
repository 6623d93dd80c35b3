// The BC6H tables. Header layouts are written as the spec's tables list them, one token per run of
// bits: "rw0-9" = RW bits 0..9 in that order, "rw15-10" = RW bits 15 down to 10, "d0-4" = the
// partition number. They are parsed at compile time into (field, bit) pairs.
#include "codecs/bc6h/bc6h_tables.h"


namespace ahd::bc6h {
namespace {

struct ModeSpec {
  uint8_t code, regions;
  bool transformed;
  uint8_t index_bits, epb, dr, dg, db;
  const char* layout;  // after the mode bits
};

constexpr ModeSpec kSpecs[kModeCount] = {
    {0x00, 2, true, 3, 10, 5, 5, 5,
     "gy4 by4 bz4 rw0-9 gw0-9 bw0-9 rx0-4 gz4 gy0-3 gx0-4 bz0 gz0-3 bx0-4 bz1 by0-3 ry0-4 bz2 rz0-4 bz3 d0-4"},
    {0x01, 2, true, 3, 7, 6, 6, 6,
     "gy5 gz4 gz5 rw0-6 bz0 bz1 by4 gw0-6 by5 bz2 gy4 bw0-6 bz3 bz5 bz4 rx0-5 gy0-3 gx0-5 gz0-3 bx0-5 by0-3 ry0-5 "
     "rz0-5 d0-4"},
    {0x02, 2, true, 3, 11, 5, 4, 4,
     "rw0-9 gw0-9 bw0-9 rx0-4 rw10 gy0-3 gx0-3 gw10 bz0 gz0-3 bx0-3 bw10 bz1 by0-3 ry0-4 bz2 rz0-4 bz3 d0-4"},
    {0x06, 2, true, 3, 11, 4, 5, 4,
     "rw0-9 gw0-9 bw0-9 rx0-3 rw10 gz4 gy0-3 gx0-4 gw10 gz0-3 bx0-3 bw10 bz1 by0-3 ry0-3 bz0 bz2 rz0-3 gy4 bz3 d0-4"},
    {0x0a, 2, true, 3, 11, 4, 4, 5,
     "rw0-9 gw0-9 bw0-9 rx0-3 rw10 by4 gy0-3 gx0-3 gw10 bz0 gz0-3 bx0-4 bw10 by0-3 ry0-3 bz1 bz2 rz0-3 bz4 bz3 d0-4"},
    {0x0e, 2, true, 3, 9, 5, 5, 5,
     "rw0-8 by4 gw0-8 gy4 bw0-8 bz4 rx0-4 gz4 gy0-3 gx0-4 bz0 gz0-3 bx0-4 bz1 by0-3 ry0-4 bz2 rz0-4 bz3 d0-4"},
    {0x12, 2, true, 3, 8, 6, 5, 5,
     "rw0-7 gz4 by4 gw0-7 bz2 gy4 bw0-7 bz3 bz4 rx0-5 gy0-3 gx0-4 bz0 gz0-3 bx0-4 bz1 by0-3 ry0-5 rz0-5 d0-4"},
    {0x16, 2, true, 3, 8, 5, 6, 5,
     "rw0-7 bz0 by4 gw0-7 gy5 gy4 bw0-7 gz5 bz4 rx0-4 gz4 gy0-3 gx0-5 gz0-3 bx0-4 bz1 by0-3 ry0-4 bz2 rz0-4 bz3 d0-4"},
    {0x1a, 2, true, 3, 8, 5, 5, 6,
     "rw0-7 bz1 by4 gw0-7 by5 gy4 bw0-7 bz5 bz4 rx0-4 gz4 gy0-3 gx0-4 bz0 gz0-3 bx0-5 by0-3 ry0-4 bz2 rz0-4 bz3 d0-4"},
    {0x1e, 2, false, 3, 6, 6, 6, 6,
     "rw0-5 gz4 bz0 bz1 by4 gw0-5 gy5 by5 bz2 gy4 bw0-5 gz5 bz3 bz5 bz4 rx0-5 gy0-3 gx0-5 gz0-3 bx0-5 by0-3 ry0-5 "
     "rz0-5 d0-4"},
    {0x03, 1, false, 4, 10, 10, 10, 10, "rw0-9 gw0-9 bw0-9 rx0-9 gx0-9 bx0-9"},
    {0x07, 1, true, 4, 11, 9, 9, 9, "rw0-9 gw0-9 bw0-9 rx0-8 rw10 gx0-8 gw10 bx0-8 bw10"},
    {0x0b, 1, true, 4, 12, 8, 8, 8, "rw0-9 gw0-9 bw0-9 rx0-7 rw11 rw10 gx0-7 gw11 gw10 bx0-7 bw11 bw10"},
    {0x0f, 1, true, 4, 16, 4, 4, 4, "rw0-9 gw0-9 bw0-9 rx0-3 rw15-10 gx0-3 gw15-10 bx0-3 bw15-10"},
};

// The field a two-letter token names ("rw" … "bz"); D for "d".
constexpr Field field_of(char a, char b) {
  constexpr char names[12][2] = {{'r', 'w'}, {'g', 'w'}, {'b', 'w'}, {'r', 'x'}, {'g', 'x'}, {'b', 'x'},
                                 {'r', 'y'}, {'g', 'y'}, {'b', 'y'}, {'r', 'z'}, {'g', 'z'}, {'b', 'z'}};
  for (int i = 0; i < 12; ++i)
    if (names[i][0] == a && names[i][1] == b) return Field(i);
  return D;
}

constexpr bool is_alpha(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); }
constexpr bool is_digit(char c) { return c >= '0' && c <= '9'; }

// Parses the layouts at compile time, so mode() is a plain table load (it sits in the encoder's
// inner loops; the run-time parse behind a function-local static cost a call and a guard check).
consteval ModeTable parse_modes() {
  ModeTable t{};
  for (int i = 0; i < kModeCount; ++i) {
    const ModeSpec& s = kSpecs[i];
    ModeInfo& o = t.m[i];
    o.code = s.code, o.regions = s.regions, o.transformed = s.transformed, o.index_bits = s.index_bits;
    o.epb = s.epb, o.delta[0] = s.dr, o.delta[1] = s.dg, o.delta[2] = s.db;
    const char* p = s.layout;
    while (*p) {
      while (*p == ' ') ++p;
      char name[2] = {0, 0};
      int len = 0;
      while (is_alpha(*p)) {
        if (len < 2) name[len] = *p;
        ++len, ++p;
      }
      int a = 0, b;
      while (is_digit(*p)) a = a * 10 + (*p++ - '0');
      b = a;
      if (*p == '-') {
        ++p;
        b = 0;
        while (is_digit(*p)) b = b * 10 + (*p++ - '0');
      }
      const Field f = len == 2 ? field_of(name[0], name[1]) : D;
      const int step = b >= a ? 1 : -1;
      for (int bit = a;; bit += step) {
        o.layout_field[o.layout_count] = f;
        o.layout_bit[o.layout_count] = uint8_t(bit);
        ++o.layout_count;
        if (bit == b) break;
      }
    }
  }
  return t;
}

}  // namespace

constinit const ModeTable kModeTable = parse_modes();



int mode_from_code(uint32_t code) {
  for (int i = 0; i < kModeCount; ++i)
    if (kSpecs[i].code == code) return i;
  return -1;
}

const uint16_t kPartitions[32] = {
    0xCCCC, 0x8888, 0xEEEE, 0xECC8, 0xC880, 0xFEEC, 0xFEC8, 0xEC80, 0xC800, 0xFFEC, 0xFE80,
    0xE800, 0xFFE8, 0xFF00, 0xFFF0, 0xF000, 0xF710, 0x008E, 0x7100, 0x08CE, 0x008C, 0x7310,
    0x3100, 0x8CCE, 0x088C, 0x3110, 0x6666, 0x366C, 0x17E8, 0x0FF0, 0x718E, 0x399C};
const uint8_t kAnchor2[32] = {15, 15, 15, 15, 15, 15, 15, 15, 15, 15, 15, 15, 15, 15, 15, 15,
                              15, 2,  8,  2,  2,  8,  8,  15, 2,  8,  2,  2,  8,  8,  2,  2};
const uint8_t kWeights3[8] = {0, 9, 18, 27, 37, 46, 55, 64};
const uint8_t kWeights4[16] = {0, 4, 9, 13, 17, 21, 26, 30, 34, 38, 43, 47, 51, 55, 60, 64};

}  // namespace ahd::bc6h
