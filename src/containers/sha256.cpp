#include "containers/sha256.h"
#include "containers/sha256_stream.h"

#include <algorithm>
#include <cstring>

#include "core/cpu.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define AHD_SHA_NI 1
#include <immintrin.h>
#endif

namespace ahd {
namespace {

constexpr uint32_t kK[64] = {
    0x428a2f98, 0x71374491, 0xb5c0fbcf, 0xe9b5dba5, 0x3956c25b, 0x59f111f1, 0x923f82a4, 0xab1c5ed5,
    0xd807aa98, 0x12835b01, 0x243185be, 0x550c7dc3, 0x72be5d74, 0x80deb1fe, 0x9bdc06a7, 0xc19bf174,
    0xe49b69c1, 0xefbe4786, 0x0fc19dc6, 0x240ca1cc, 0x2de92c6f, 0x4a7484aa, 0x5cb0a9dc, 0x76f988da,
    0x983e5152, 0xa831c66d, 0xb00327c8, 0xbf597fc7, 0xc6e00bf3, 0xd5a79147, 0x06ca6351, 0x14292967,
    0x27b70a85, 0x2e1b2138, 0x4d2c6dfc, 0x53380d13, 0x650a7354, 0x766a0abb, 0x81c2c92e, 0x92722c85,
    0xa2bfe8a1, 0xa81a664b, 0xc24b8b70, 0xc76c51a3, 0xd192e819, 0xd6990624, 0xf40e3585, 0x106aa070,
    0x19a4c116, 0x1e376c08, 0x2748774c, 0x34b0bcb5, 0x391c0cb3, 0x4ed8aa4a, 0x5b9cca4f, 0x682e6ff3,
    0x748f82ee, 0x78a5636f, 0x84c87814, 0x8cc70208, 0x90befffa, 0xa4506ceb, 0xbef9a3f7, 0xc67178f2};

inline uint32_t rotr(uint32_t x, int n) { return (x >> n) | (x << (32 - n)); }

void compress(uint32_t h[8], const uint8_t block[64]) {
  uint32_t w[64];
  for (int i = 0; i < 16; ++i)
    w[i] = uint32_t(block[4 * i]) << 24 | uint32_t(block[4 * i + 1]) << 16 | uint32_t(block[4 * i + 2]) << 8 |
           uint32_t(block[4 * i + 3]);
  for (int i = 16; i < 64; ++i) {
    const uint32_t s0 = rotr(w[i - 15], 7) ^ rotr(w[i - 15], 18) ^ (w[i - 15] >> 3);
    const uint32_t s1 = rotr(w[i - 2], 17) ^ rotr(w[i - 2], 19) ^ (w[i - 2] >> 10);
    w[i] = w[i - 16] + s0 + w[i - 7] + s1;
  }
  uint32_t a = h[0], b = h[1], c = h[2], d = h[3], e = h[4], f = h[5], g = h[6], k = h[7];
  for (int i = 0; i < 64; ++i) {
    const uint32_t t1 = k + (rotr(e, 6) ^ rotr(e, 11) ^ rotr(e, 25)) + ((e & f) ^ (~e & g)) + kK[i] + w[i];
    const uint32_t t2 = (rotr(a, 2) ^ rotr(a, 13) ^ rotr(a, 22)) + ((a & b) ^ (a & c) ^ (b & c));
    k = g, g = f, f = e, e = d + t1, d = c, c = b, b = a, a = t1 + t2;
  }
  h[0] += a, h[1] += b, h[2] += c, h[3] += d, h[4] += e, h[5] += f, h[6] += g, h[7] += k;
}

void compress_blocks(uint32_t h[8], const uint8_t* data, size_t blocks) {
  for (size_t b = 0; b < blocks; ++b) compress(h, data + 64 * b);
}

#ifdef AHD_SHA_NI
// The same compression with the SHA extensions: sha256rnds2 does two rounds on the state held as
// (A, B, E, F) and (C, D, G, H) lanes, sha256msg1/msg2 the message schedule's σ0 and σ1 parts.
__attribute__((target("sha,sse4.1,ssse3"))) void compress_blocks_ni(uint32_t h[8], const uint8_t* data,
                                                                     size_t blocks) {
  const __m128i bswap = _mm_set_epi8(12, 13, 14, 15, 8, 9, 10, 11, 4, 5, 6, 7, 0, 1, 2, 3);
  __m128i abcd = _mm_loadu_si128(reinterpret_cast<const __m128i*>(h));
  __m128i efgh = _mm_loadu_si128(reinterpret_cast<const __m128i*>(h + 4));
  abcd = _mm_shuffle_epi32(abcd, 0xB1);                 // B A D C
  efgh = _mm_shuffle_epi32(efgh, 0x1B);                 // H G F E
  __m128i abef = _mm_alignr_epi8(abcd, efgh, 8);        // F E B A (lane 3 = A)
  __m128i cdgh = _mm_blend_epi16(efgh, abcd, 0xF0);     // H G D C
  for (size_t b = 0; b < blocks; ++b, data += 64) {
    const __m128i abef0 = abef, cdgh0 = cdgh;
    __m128i m[4];
    for (int g = 0; g < 16; ++g) {
      __m128i& w = m[g & 3];
      if (g < 4) {
        w = _mm_shuffle_epi8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(data + 16 * g)), bswap);
      } else {
        // W[t..t+3] = σ1(W[t-2..]) + W[t-7..] + σ0(W[t-15..]) + W[t-16..], four at a time.
        const __m128i w7 = _mm_alignr_epi8(m[(g - 1) & 3], m[(g - 2) & 3], 4);
        w = _mm_sha256msg2_epu32(_mm_add_epi32(_mm_sha256msg1_epu32(w, m[(g - 3) & 3]), w7), m[(g - 1) & 3]);
      }
      __m128i k = _mm_add_epi32(w, _mm_loadu_si128(reinterpret_cast<const __m128i*>(kK + 4 * g)));
      cdgh = _mm_sha256rnds2_epu32(cdgh, abef, k);
      k = _mm_shuffle_epi32(k, 0x0E);
      abef = _mm_sha256rnds2_epu32(abef, cdgh, k);
    }
    abef = _mm_add_epi32(abef, abef0);
    cdgh = _mm_add_epi32(cdgh, cdgh0);
  }
  const __m128i feba = _mm_shuffle_epi32(abef, 0x1B);   // A B E F
  const __m128i dchg = _mm_shuffle_epi32(cdgh, 0xB1);   // G H C D
  _mm_storeu_si128(reinterpret_cast<__m128i*>(h), _mm_blend_epi16(feba, dchg, 0xF0));      // A B C D
  _mm_storeu_si128(reinterpret_cast<__m128i*>(h + 4), _mm_alignr_epi8(dchg, feba, 8));  // E F G H
}
#endif

}  // namespace

bool sha256_hardware() {
#ifdef AHD_SHA_NI
  return cpu::has(cpu::kShaNi);
#else
  return false;
#endif
}

namespace {

using BlockFn = void (*)(uint32_t[8], const uint8_t*, size_t);

BlockFn block_fn(Sha256Path path) {
#ifdef AHD_SHA_NI
  if (path == Sha256Path::Best && sha256_hardware()) return compress_blocks_ni;
#else
  (void)path;
#endif
  return compress_blocks;
}

// The padding (0x80, zeros, the message length in bits, big-endian, in the last 8 bytes) after the
// `rest` < 64 buffered bytes of a `size`-byte message, then the digest as hex.
std::string finish(uint32_t h[8], const uint8_t* rest_data, size_t rest, uint64_t size, BlockFn blocks) {
  uint8_t tail[128] = {};
  if (rest) std::memcpy(tail, rest_data, rest);
  tail[rest] = 0x80;
  const size_t tail_len = rest + 9 <= 64 ? 64 : 128;
  const uint64_t bits = size * 8;
  for (int b = 0; b < 8; ++b) tail[tail_len - 1 - b] = uint8_t(bits >> (8 * b));
  blocks(h, tail, tail_len / 64);
  static const char* hex = "0123456789abcdef";
  std::string out(64, '0');
  for (int j = 0; j < 8; ++j)
    for (int b = 0; b < 8; ++b) out[size_t(j * 8 + b)] = hex[(h[j] >> (28 - 4 * b)) & 0xF];
  return out;
}

}  // namespace

std::string sha256_hex(const uint8_t* data, size_t size, Sha256Path path) {
  uint32_t h[8] = {0x6a09e667, 0xbb67ae85, 0x3c6ef372, 0xa54ff53a, 0x510e527f, 0x9b05688c, 0x1f83d9ab, 0x5be0cd19};
  const BlockFn blocks = block_fn(path);
  const size_t i = size / 64 * 64;
  blocks(h, data, size / 64);
  return finish(h, data + i, size - i, size, blocks);
}

void Sha256::update(const uint8_t* data, size_t size) {
  const BlockFn blocks = block_fn(Sha256Path::Best);
  total_ += size;
  if (buffered_) {
    const size_t take = std::min(size, 64 - buffered_);
    std::memcpy(buf_ + buffered_, data, take);
    buffered_ += take, data += take, size -= take;
    if (buffered_ < 64) return;
    blocks(h_, buf_, 1);
    buffered_ = 0;
  }
  blocks(h_, data, size / 64);
  const size_t i = size / 64 * 64;
  std::memcpy(buf_, data + i, size - i);
  buffered_ = size - i;
}

std::string Sha256::hex() { return finish(h_, buf_, buffered_, total_, block_fn(Sha256Path::Best)); }

}  // namespace ahd
