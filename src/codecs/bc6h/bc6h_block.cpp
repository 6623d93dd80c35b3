// BC6H decoding of one block, exactly as the specification reads it.
#include <Imath/half.h>

#include "codecs/bc6h/bc6h_codec.h"
#include "codecs/bc6h/bc6h_tables.h"
#include "core/parallel.h"

namespace ahd {

using namespace bc6h;

namespace {

// The block's 128 bits as two words: a field of up to 32 bits at any position in one shift or two
// (issue 45: the bit-at-a-time reader was 10 % of a small plain map's instructions, the error
// estimate decoding one texel of a block at a time).
struct BitReader {
  uint64_t lo = 0, hi = 0;
  int pos = 0;
  explicit BitReader(const uint8_t* b) {
    for (int i = 0; i < 8; ++i) lo |= uint64_t(b[i]) << (8 * i), hi |= uint64_t(b[8 + i]) << (8 * i);
  }
  // n bits (n ≤ 32) from bit p, the first in bit 0.
  int peek(int p, int n) const {
    const uint64_t v = p >= 64 ? hi >> (p - 64) : p == 0 ? lo : (lo >> p) | (hi << (64 - p));
    return int(v & ((uint64_t(1) << n) - 1));
  }
  int get(int n) {
    const int v = peek(pos, n);
    pos += n;
    return v;
  }
};

// A mode's header layout as runs: consecutive positions that hold consecutive bits of one field
// (the spec's per-bit layout, ModeInfo::layout_field/bit, merged), so a header is read a run at a
// time (most fields are one run; the reversed ones, a run per bit).
struct LayoutRun {
  uint8_t field, first_bit, length;
};
struct ModeRuns {
  uint8_t count = 0;
  LayoutRun run[80];
};
struct RunTable {
  ModeRuns m[kModeCount];
  RunTable() {
    for (int k = 0; k < kModeCount; ++k) {
      const ModeInfo& mi = mode(k);
      ModeRuns& r = m[k];
      for (int i = 0; i < mi.layout_count; ++i) {
        LayoutRun* last = r.count ? &r.run[r.count - 1] : nullptr;
        if (last && last->field == mi.layout_field[i] && last->first_bit + last->length == mi.layout_bit[i]) ++last->length;
        else r.run[r.count++] = {mi.layout_field[i], mi.layout_bit[i], 1};
      }
    }
  }
};
const RunTable kRuns;

// A block's header as the specification reads it: its mode, partition and unquantised endpoints,
// with the reader left at the first index bit. False for the reserved modes.
struct Header {
  const ModeInfo* mi = nullptr;
  int u[12];  // unquantised endpoints: region r's pair at u[r*6 .. r*6+6)
  uint16_t mask = 0;  // the partition: bit t set when texel t lies in region 1
  int anchor = -1;    // region 1's anchor texel (two regions)
};

bool read_header(BitReader& r, bool is_signed, Header* h) {
  int code = r.get(2);
  if (code > 1) code |= r.get(3) << 2;
  const int m = mode_from_code(uint32_t(code));
  if (m < 0) return false;
  const ModeInfo& mi = mode(m);
  int e[12] = {};  // RW GW BW RX GX BX RY GY BY RZ GZ BZ
  int partition = 0;
  const ModeRuns& runs = kRuns.m[m];
  for (int i = 0; i < runs.count; ++i) {
    const LayoutRun& run = runs.run[i];
    const int bits = r.get(run.length);
    if (run.field == D) partition |= bits << run.first_bit;
    else e[run.field] |= bits << run.first_bit;
  }
  const int ends = mi.regions * 2;
  // Sign extension and the delta transform.
  for (int c = 0; c < 3; ++c) {
    if (is_signed) e[c] = sign_extend(e[c], mi.epb);
    for (int k = 1; k < ends; ++k) {
      int& v = e[k * 3 + c];
      if (mi.transformed) {
        v = sign_extend(v, mi.delta[c]);
        v = (e[c] + v) & ((1 << mi.epb) - 1);
        if (is_signed) v = sign_extend(v, mi.epb);
      } else if (is_signed) {
        v = sign_extend(v, mi.epb);
      }
    }
  }
  for (int k = 0; k < ends * 3; ++k) h->u[k] = unquantize(e[k], mi.epb, is_signed);
  h->mi = &mi;
  h->mask = mi.regions == 2 ? kPartitions[partition] : 0;
  h->anchor = mi.regions == 2 ? kAnchor2[partition] : -1;
  return true;
}

// Texel t of the block, its index read at the reader's position.
void decode_texel_at(BitReader& r, const Header& h, bool is_signed, int t, uint16_t out[3]) {
  const ModeInfo& mi = *h.mi;
  const int nbits = (t == 0 || t == h.anchor) ? mi.index_bits - 1 : mi.index_bits;
  const int idx = r.get(nbits);
  const uint8_t* weights = mi.index_bits == 3 ? kWeights3 : kWeights4;
  const int* a = &h.u[((h.mask >> t) & 1) * 6];
  for (int c = 0; c < 3; ++c) out[c] = finish_unquantize(interpolate(a[c], a[3 + c], weights[idx]), is_signed);
}

}  // namespace

void bc6h_decode_block(const uint8_t block[16], bool is_signed, uint16_t out[48]) {
  BitReader r(block);
  Header h;
  if (!read_header(r, is_signed, &h)) {  // reserved: the spec decodes these to 0
    for (int i = 0; i < 48; ++i) out[i] = 0;
    return;
  }
  for (int t = 0; t < 16; ++t) decode_texel_at(r, h, is_signed, t, &out[t * 3]);
}

void bc6h_decode_texel(const uint8_t block[16], bool is_signed, int t, uint16_t out[3]) {
  BitReader r(block);
  Header h;
  if (!read_header(r, is_signed, &h)) {
    out[0] = out[1] = out[2] = 0;
    return;
  }
  // Texel t's index follows those of texels 0 .. t-1, each index_bits long except texel 0's and
  // the anchor's, one bit shorter.
  r.pos += t * h.mi->index_bits - (t > 0 ? 1 : 0) - (h.anchor >= 0 && t > h.anchor ? 1 : 0);
  decode_texel_at(r, h, is_signed, t, out);
}

ImageF bc6h_decode_image(const uint8_t* blocks, int width, int height, bool is_signed) {
  ImageF img(width, height, 3);
  const int bw = (width + 3) / 4, bh = (height + 3) / 4;
  parallel_for(size_t(bw) * bh, 0, 256, [&](size_t b) {
    const int bx = int(b % bw), by = int(b / bw);
    uint16_t h[48];
    bc6h_decode_block(blocks + b * 16, is_signed, h);
    for (int t = 0; t < 16; ++t) {
      const int x = bx * 4 + t % 4, y = by * 4 + t / 4;
      if (x >= width || y >= height) continue;
      for (int c = 0; c < 3; ++c) {
        Imath::half v;
        v.setBits(h[t * 3 + c]);
        img.at(x, y)[c] = float(v);
      }
    }
  });
  return img;
}

}  // namespace ahd
