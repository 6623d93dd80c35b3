#include "image/exr_zip.h"

#include <atomic>
#include <cstring>
#include <vector>

#include "core/cpu.h"

#if defined(AHD_HAVE_LIBDEFLATE)
#include <libdeflate.h>
#endif
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace ahd {

namespace {
std::atomic<bool> g_enabled{true};

// The predictor: byte i was stored as its difference from byte i − 1, plus 128 (mod 256), so the
// bytes are the running sums of (stored − 128) from byte 1 on. Sixteen at a time with SSE2: a
// prefix sum within the register in four shifted adds, plus the last byte of the sixteen before.
// Sums mod 256 in any grouping are the same bytes as the one-by-one loop (the plain loop when
// cpu::kSse2 is off: test ExrZip.SimdAndPlainLoopsGiveTheSameBytes).
void undo_predictor(uint8_t* t, size_t size) {
  size_t i = 1;
#if defined(__SSE2__)
  if (cpu::has(cpu::kSse2)) {
    const __m128i bias = _mm_set1_epi8(char(-128));
    __m128i carry = _mm_set1_epi8(char(t[0]));
    for (; i + 16 <= size; i += 16) {
      __m128i x = _mm_add_epi8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(t + i)), bias);
      x = _mm_add_epi8(x, _mm_slli_si128(x, 1));
      x = _mm_add_epi8(x, _mm_slli_si128(x, 2));
      x = _mm_add_epi8(x, _mm_slli_si128(x, 4));
      x = _mm_add_epi8(x, _mm_slli_si128(x, 8));
      x = _mm_add_epi8(x, carry);
      _mm_storeu_si128(reinterpret_cast<__m128i*>(t + i), x);
      carry = _mm_set1_epi8(char(t[i + 15]));
    }
  }
#endif
  for (; i < size; ++i) t[i] = uint8_t(t[i - 1] + t[i] - 128);
}

// The halves: bytes 0, 2, 4, … of `out` are the first (size + 1) / 2 of `t`, bytes 1, 3, 5, … the rest.
void interleave_halves(const uint8_t* t, uint8_t* out, size_t size) {
  const uint8_t* a = t;
  const uint8_t* b = t + (size + 1) / 2;
  const size_t pairs = size / 2;
  size_t k = 0;
#if defined(__SSE2__)
  for (const bool simd = cpu::has(cpu::kSse2); simd && k + 16 <= pairs; k += 16) {
    const __m128i x = _mm_loadu_si128(reinterpret_cast<const __m128i*>(a + k));
    const __m128i y = _mm_loadu_si128(reinterpret_cast<const __m128i*>(b + k));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 2 * k), _mm_unpacklo_epi8(x, y));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 2 * k + 16), _mm_unpackhi_epi8(x, y));
  }
#endif
  for (; k < pairs; ++k) out[2 * k] = a[k], out[2 * k + 1] = b[k];
  if (size & 1) out[size - 1] = a[pairs];
}
}  // namespace

bool exr_zip_available() {
#if defined(AHD_HAVE_LIBDEFLATE)
  return g_enabled.load(std::memory_order_relaxed);
#else
  return false;
#endif
}

void set_exr_zip_enabled(bool on) { g_enabled.store(on, std::memory_order_relaxed); }

void exr_zip_unpack(uint8_t* t, uint8_t* out, size_t size) {
  if (size == 0) return;
  undo_predictor(t, size);
  interleave_halves(t, out, size);
}

bool exr_unzip_chunk(const uint8_t* raw, size_t n, uint8_t* out, size_t size) {
  if (n >= size) {  // OpenEXR stores a chunk that would not shrink as it is (and reads its first bytes)
    std::memcpy(out, raw, size);
    return true;
  }
#if defined(AHD_HAVE_LIBDEFLATE)
  struct Decompressor {
    libdeflate_decompressor* d = libdeflate_alloc_decompressor();
    ~Decompressor() { libdeflate_free_decompressor(d); }
  };
  thread_local Decompressor dec;
  thread_local std::vector<uint8_t> tmp;
  if (!dec.d) return false;
  if (tmp.size() < size) tmp.resize(size);
  size_t got = 0;
  if (libdeflate_zlib_decompress(dec.d, raw, n, tmp.data(), size, &got) != LIBDEFLATE_SUCCESS || got != size)
    return false;
  exr_zip_unpack(tmp.data(), out, size);
  return true;
#else
  return false;
#endif
}

}  // namespace ahd
