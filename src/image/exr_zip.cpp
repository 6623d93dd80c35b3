#include "image/exr_zip.h"

#include <atomic>
#include <cstring>
#include <memory>
#include <vector>

#if defined(AHD_HAVE_LIBDEFLATE)
#include <libdeflate.h>
#endif

namespace ahd {

namespace {
std::atomic<bool> g_enabled{true};
}  // namespace

bool exr_zip_available() {
#if defined(AHD_HAVE_LIBDEFLATE)
  return g_enabled.load(std::memory_order_relaxed);
#else
  return false;
#endif
}

void set_exr_zip_enabled(bool on) { g_enabled.store(on, std::memory_order_relaxed); }

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
  // The predictor: each byte was stored as its difference from the one before, plus 128.
  uint8_t* t = tmp.data();
  for (size_t i = 1; i < size; ++i) t[i] = uint8_t(t[i - 1] + t[i] - 128);
  // The halves: bytes 0, 2, 4, … first, then 1, 3, 5, ….
  const uint8_t* a = t;
  const uint8_t* b = t + (size + 1) / 2;
  size_t i = 0;
  for (; i + 1 < size; i += 2) out[i] = *a++, out[i + 1] = *b++;
  if (i < size) out[i] = *a;
  return true;
#else
  return false;
#endif
}

}  // namespace ahd
