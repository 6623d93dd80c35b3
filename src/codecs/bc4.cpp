#include "codecs/bc4.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "core/cpu.h"
#include "core/parallel.h"

#ifdef __SSE2__
#include <emmintrin.h>
#include <immintrin.h>
#endif

namespace ahd {
namespace {

#ifdef __SSE2__
// The index step on wider lanes: the 16 texels in one AVX-512 register or two AVX2 ones (the
// SSE2 loop below needs four). Each lane does what the scalar loop does — |v − p|, a strict
// compare, a select — so the distances and indices are bit for bit the same; the caller sums the
// error in texel order (outside these functions, so no FMA can fuse it). Issue 28: `assign` was
// 18 % of an L2 2048² conversion's samples with the SSE2 loop.
__attribute__((target("avx512f"))) void nearest_avx512(const float v[16], const float pal[8], float bd[16], int bi[16]) {
  const __m512 vi = _mm512_loadu_ps(v);
  __m512 d = _mm512_abs_ps(_mm512_sub_ps(vi, _mm512_set1_ps(pal[0])));
  __m512i kb = _mm512_setzero_si512();
  for (int k = 1; k < 8; ++k) {
    const __m512 dk = _mm512_abs_ps(_mm512_sub_ps(vi, _mm512_set1_ps(pal[k])));
    const __mmask16 closer = _mm512_cmp_ps_mask(dk, d, _CMP_LT_OQ);
    d = _mm512_mask_mov_ps(d, closer, dk);
    kb = _mm512_mask_mov_epi32(kb, closer, _mm512_set1_epi32(k));
  }
  _mm512_storeu_ps(bd, d);
  _mm512_storeu_si512(bi, kb);
}

__attribute__((target("avx2"))) void nearest_avx2(const float v[16], const float pal[8], float bd[16], int bi[16]) {
  const __m256 sign = _mm256_set1_ps(-0.0f);
  const __m256 v0 = _mm256_loadu_ps(v), v1 = _mm256_loadu_ps(v + 8);
  const __m256 p0 = _mm256_set1_ps(pal[0]);
  __m256 d0 = _mm256_andnot_ps(sign, _mm256_sub_ps(v0, p0)), d1 = _mm256_andnot_ps(sign, _mm256_sub_ps(v1, p0));
  __m256 k0 = _mm256_setzero_ps(), k1 = _mm256_setzero_ps();  // indices as int bits in float lanes
  for (int k = 1; k < 8; ++k) {
    const __m256 pk = _mm256_set1_ps(pal[k]);
    const __m256 kk = _mm256_castsi256_ps(_mm256_set1_epi32(k));
    const __m256 e0 = _mm256_andnot_ps(sign, _mm256_sub_ps(v0, pk)), e1 = _mm256_andnot_ps(sign, _mm256_sub_ps(v1, pk));
    const __m256 c0 = _mm256_cmp_ps(e0, d0, _CMP_LT_OQ), c1 = _mm256_cmp_ps(e1, d1, _CMP_LT_OQ);
    d0 = _mm256_blendv_ps(d0, e0, c0), d1 = _mm256_blendv_ps(d1, e1, c1);
    k0 = _mm256_blendv_ps(k0, kk, c0), k1 = _mm256_blendv_ps(k1, kk, c1);
  }
  _mm256_storeu_ps(bd, d0);
  _mm256_storeu_ps(bd + 8, d1);
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(bi), _mm256_castps_si256(k0));
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(bi + 8), _mm256_castps_si256(k1));
}
#endif

uint64_t read_indices(const uint8_t* b) {
  uint64_t v = 0;
  for (int i = 0; i < 6; ++i) v |= uint64_t(b[2 + i]) << (8 * i);
  return v;
}

#ifdef __SSE2__
// Four texels per SSE2 register (g++ 12 left the plain loops scalar: issue 28, perf of an L2
// 2048² conversion put the index step at 25 % of its samples).
void nearest_sse2(const float v[16], const float pal[8], float bd[16], int bi[16]) {
  const __m128 sign = _mm_set1_ps(-0.0f);
  __m128 d[4], vi[4];
  __m128i k_best[4];
  const __m128 p0 = _mm_set1_ps(pal[0]);
  for (int q = 0; q < 4; ++q) {
    vi[q] = _mm_loadu_ps(v + 4 * q);
    d[q] = _mm_andnot_ps(sign, _mm_sub_ps(vi[q], p0));
    k_best[q] = _mm_setzero_si128();
  }
  for (int k = 1; k < 8; ++k) {
    const __m128 pk = _mm_set1_ps(pal[k]);
    const __m128i kk = _mm_set1_epi32(k);
    for (int q = 0; q < 4; ++q) {
      const __m128 dk = _mm_andnot_ps(sign, _mm_sub_ps(vi[q], pk));
      const __m128 closer = _mm_cmplt_ps(dk, d[q]);
      d[q] = _mm_or_ps(_mm_and_ps(closer, dk), _mm_andnot_ps(closer, d[q]));
      const __m128i c = _mm_castps_si128(closer);
      k_best[q] = _mm_or_si128(_mm_and_si128(c, kk), _mm_andnot_si128(c, k_best[q]));
    }
  }
  for (int q = 0; q < 4; ++q) {
    _mm_storeu_ps(bd + 4 * q, d[q]);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(bi + 4 * q), k_best[q]);
  }
}
#endif

// The plain loops, which every path above matches lane for lane.
void nearest_scalar(const float v[16], const float pal[8], float bd[16], int bi[16]) {
  for (int i = 0; i < 16; ++i) bd[i] = std::fabs(v[i] - pal[0]), bi[i] = 0;
  for (int k = 1; k < 8; ++k)
    for (int i = 0; i < 16; ++i) {
      const float d = std::fabs(v[i] - pal[k]);
      const bool closer = d < bd[i];
      bd[i] = closer ? d : bd[i];
      bi[i] = closer ? k : bi[i];
    }
}

using NearestFn = void (*)(const float*, const float*, float*, int*);

// The widest index step this CPU has (asked once per block: the tests switch paths between calls).
NearestFn nearest_for_cpu() {
#ifdef __SSE2__
  if (cpu::has(cpu::kAvx512)) return nearest_avx512;
  if (cpu::has(cpu::kAvx2)) return nearest_avx2;
  if (cpu::has(cpu::kSse2)) return nearest_sse2;  // off only when the tests force the plain loops
#endif
  return nearest_scalar;
}

// Best index per texel for a palette (the first of equally close entries); returns the squared
// error, summed in texel order.
float assign(NearestFn nearest, const float v[16], const float pal[8], uint8_t idx[16]) {
  float bd[16];
  int bi[16];
  nearest(v, pal, bd, bi);
  float err = 0;
  for (int i = 0; i < 16; ++i) {
    idx[i] = uint8_t(bi[i]);
    err += bd[i] * bd[i];
  }
  return err;
}

// The endpoint pairs a block's search has already evaluated: the searches below revisit many pairs
// (neighbourhoods overlap), and a pair seen before can never win again (ties keep the first).
class TriedPairs {
 public:
  // True the first time (r0, r1) is asked about.
  bool first_time(int r0, int r1) {
    const unsigned key = unsigned(r0) << 8 | unsigned(r1);
    uint64_t& word = bits_[key >> 6];
    const uint64_t bit = uint64_t(1) << (key & 63);
    if (word & bit) return false;
    if (word == 0) touched_[ntouched_++] = uint16_t(key >> 6);
    word |= bit;
    return true;
  }
  // Forget every pair (clears only the words in use).
  void clear() {
    for (int i = 0; i < ntouched_; ++i) bits_[touched_[i]] = 0;
    ntouched_ = 0;
  }

 private:
  uint64_t bits_[1024] = {};
  uint16_t touched_[1024];
  int ntouched_ = 0;
};

void write_block(uint8_t r0, uint8_t r1, const uint8_t idx[16], uint8_t out[8]) {
  out[0] = r0;
  out[1] = r1;
  uint64_t bits = 0;
  for (int i = 0; i < 16; ++i) bits |= uint64_t(idx[i] & 7) << (3 * i);
  for (int i = 0; i < 6; ++i) out[2 + i] = uint8_t(bits >> (8 * i));
}

}  // namespace

namespace {

// n / (steps·255) rounded to float, for every numerator an interpolated entry can have
// (n = (steps+1−k)·r0 + (k−1)·r1 ≤ steps·255): the encoder's search asks for palettes millions of
// times, and a table lookup gives the very value of the division.
struct InterpolationTable {
  float v[7 * 255 + 1];
  explicit InterpolationTable(int steps) {
    for (int n = 0; n <= steps * 255; ++n) v[n] = float(n / (steps * 255.0));
  }
};

}  // namespace


void bc4_palette(uint8_t r0, uint8_t r1, float pal[8]) {
  static const InterpolationTable by7(7), by5(5);
  pal[0] = r0 / 255.0f;
  pal[1] = r1 / 255.0f;
  if (r0 > r1) {
    for (int k = 2; k < 8; ++k) pal[k] = by7.v[(8 - k) * r0 + (k - 1) * r1];
  } else {
    for (int k = 2; k < 6; ++k) pal[k] = by5.v[(6 - k) * r0 + (k - 1) * r1];
    pal[6] = 0.0f;
    pal[7] = 1.0f;
  }
}

void bc4_decode_block(const uint8_t block[8], float out[16]) {
  float pal[8];
  bc4_palette(block[0], block[1], pal);
  const uint64_t bits = read_indices(block);
  for (int i = 0; i < 16; ++i) out[i] = pal[(bits >> (3 * i)) & 7];
}

void bc4_decode_block_unorm8(const uint8_t block[8], uint8_t out[16]) {
  const int r0 = block[0], r1 = block[1];
  const bool eight = r0 > r1;
  const uint32_t step = eight ? 255 * 64 / 7 : 255 * 64 / 5;
  uint8_t pal[8] = {uint8_t(r0), uint8_t(r1), 0, 0, 0, 0, 0, 255};
  for (int k = 2; k < (eight ? 8 : 6); ++k) {
    const uint32_t w = (step * uint32_t(k - 1)) >> 6;             // weight in 1/256 units
    const uint32_t delta = uint32_t(r1 - r0) & 0xFFFF;            // 16-bit lane arithmetic
    const uint32_t interp = ((delta * w) & 0xFFFF) >> 8;
    pal[k] = uint8_t(r0 + interp);                                // 8-bit wrap-around add
  }
  const uint64_t bits = read_indices(block);
  for (int i = 0; i < 16; ++i) out[i] = pal[(bits >> (3 * i)) & 7];
}

void bc4_encode_block(const float texels[16], uint8_t out[8], int effort) {
  float v[16];
  float lo = 1.0f, hi = 0.0f;
  for (int i = 0; i < 16; ++i) {
    v[i] = std::clamp(std::isfinite(texels[i]) ? texels[i] : 0.0f, 0.0f, 1.0f);
    lo = std::min(lo, v[i]);
    hi = std::max(hi, v[i]);
  }
  const int qlo = int(std::floor(lo * 255.0f)), qhi = int(std::ceil(hi * 255.0f));
  if (qlo == qhi) {  // constant block: exact with r0 = r1 (6-value mode, every index 0)
    const uint8_t idx[16] = {};
    const uint8_t q = uint8_t(std::lround(v[0] * 255.0f));
    write_block(q, q, idx, out);
    return;
  }
  const int radius = effort <= 0 ? 0 : effort == 1 ? 2 : 4;
  float best = INFINITY;
  uint8_t best_idx[16], idx[16], b0 = 0, b1 = 0;
  float pal[8];
  thread_local TriedPairs tried;
  tried.clear();
  const NearestFn nearest = nearest_for_cpu();
  auto consider = [&](int r0, int r1) {
    if (r0 < 0 || r0 > 255 || r1 < 0 || r1 > 255) return;
    if (!tried.first_time(r0, r1)) return;
    bc4_palette(uint8_t(r0), uint8_t(r1), pal);
    const float e = assign(nearest, v, pal, idx);
    if (e < best) {
      best = e, b0 = uint8_t(r0), b1 = uint8_t(r1);
      std::copy(idx, idx + 16, best_idx);
    }
  };
  // 8-value mode: r0 > r1, endpoints near the range (hi, lo).
  for (int a = -radius; a <= radius; ++a)
    for (int b = -radius; b <= radius; ++b)
      if (qhi + a > qlo + b) consider(qhi + a, qlo + b);
  // 6-value mode (r0 ≤ r1) with exact 0 and 1 available: endpoints span the values strictly
  // inside (0, 1), which helps blocks that touch the ends of the range.
  float ilo = 1.0f, ihi = 0.0f;
  for (float x : v)
    if (x > 0.0f && x < 1.0f) ilo = std::min(ilo, x), ihi = std::max(ihi, x);
  if (ilo <= ihi) {
    const int plo = int(std::floor(ilo * 255.0f)), phi = int(std::ceil(ihi * 255.0f));
    for (int a = -radius; a <= radius; ++a)
      for (int b = -radius; b <= radius; ++b)
        if (plo + a <= phi + b) consider(plo + a, phi + b);
  }
  // Ramps and clusters often fit best with endpoints BEYOND the data range, so that the data's
  // min and max land on inner palette entries: try every pair of palette positions for them.
  if (effort > 0) {
    for (int mode = 0; mode < 2; ++mode) {
      const bool eight = mode == 0;
      const int steps = eight ? 7 : 5;
      const float lo8 = (eight ? lo : ilo) * 255.0f, hi8 = (eight ? hi : ihi) * 255.0f;
      if (!(hi8 > lo8)) continue;
      for (int ta = 0; ta < steps; ++ta)
        for (int tb = ta + 1; tb <= steps; ++tb) {
          const float d = (hi8 - lo8) * steps / float(tb - ta);
          const float base = lo8 - d * ta / steps;  // palette value at t = 0
          const int b = int(std::lround(base)), top = int(std::lround(base + d));
          for (int da = -(effort > 1); da <= (effort > 1); ++da)
            for (int db = -(effort > 1); db <= (effort > 1); ++db) {
              // 8-value mode ascends from r1 to r0; 6-value mode from r0 to r1.
              if (eight && top + da > b + db) consider(top + da, b + db);
              if (!eight && b + db <= top + da) consider(b + db, top + da);
            }
        }
    }
  }
  // Least-squares refinement: with the indices fixed, the best real endpoints solve a 2×2 system
  // (each palette entry is (1−f)·r0 + f·r1); round, re-assign, repeat, and look around the result.
  if (effort > 0) {
    for (int iter = 0; iter < 2 + 2 * effort; ++iter) {
      const bool eight = b0 > b1;
      double s00 = 0, s01 = 0, s11 = 0, t0 = 0, t1 = 0;
      for (int i = 0; i < 16; ++i) {
        const int k = best_idx[i];
        if (!eight && k >= 6) continue;  // exact 0 / 1 entries do not depend on the endpoints
        const double f = k == 0 ? 0.0 : k == 1 ? 1.0 : (k - 1) / (eight ? 7.0 : 5.0);
        const double x = v[i] * 255.0;
        s00 += (1 - f) * (1 - f), s01 += (1 - f) * f, s11 += f * f;
        t0 += (1 - f) * x, t1 += f * x;
      }
      const double det = s00 * s11 - s01 * s01;
      if (std::fabs(det) < 1e-9) break;
      const int e0 = int(std::lround((t0 * s11 - s01 * t1) / det)), e1 = int(std::lround((s00 * t1 - s01 * t0) / det));
      const uint8_t p0 = b0, p1 = b1;
      for (int a = -1; a <= 1; ++a)
        for (int b = -1; b <= 1; ++b) {
          const int r0 = std::clamp(e0 + a, 0, 255), r1 = std::clamp(e1 + b, 0, 255);
          if ((r0 > r1) == eight) consider(r0, r1);
        }
      if (p0 == b0 && p1 == b1) break;
    }
  }
  write_block(b0, b1, best_idx, out);
}

std::vector<uint8_t> bc4_encode_image(const ImageF& img, int channel, int threads, int effort) {
  const int bw = (img.width + 3) / 4, bh = (img.height + 3) / 4;
  std::vector<uint8_t> out(size_t(bw) * bh * 8);
  parallel_for(size_t(bw) * bh, threads, 64, [&](size_t b) {
    const int bx = int(b % bw), by = int(b / bw);
    float v[16];
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x) {
        const int sx = std::min(bx * 4 + x, img.width - 1), sy = std::min(by * 4 + y, img.height - 1);
        v[y * 4 + x] = img.at(sx, sy)[channel];
      }
    bc4_encode_block(v, &out[b * 8], effort);
  });
  return out;
}

void bc4_decode_image(const uint8_t* blocks, int width, int height, int stride, int offset, ImageF& out, int channel) {
  const int bw = (width + 3) / 4, bh = (height + 3) / 4;
  for (int by = 0; by < bh; ++by)
    for (int bx = 0; bx < bw; ++bx) {
      float v[16];
      bc4_decode_block(blocks + (size_t(by) * bw + bx) * stride + offset, v);
      for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
          const int px = bx * 4 + x, py = by * 4 + y;
          if (px < width && py < height) out.at(px, py)[channel] = v[y * 4 + x];
        }
    }
}

}  // namespace ahd
