// floats_to_half with the F16C instructions (AVX + F16C, eight floats per conversion).
#include "codecs/bc6h/bc6h_fast.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>

namespace ahd::bc6h {

__attribute__((target("avx,f16c"))) void floats_to_half_f16c(const float* in, uint16_t* out, int n) {
  int i = 0;
  for (; i + 8 <= n; i += 8) {
    const __m128i h = _mm256_cvtps_ph(_mm256_loadu_ps(in + i), _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i), h);
  }
  if (i < n) floats_to_half_portable(in + i, out + i, n - i);
}

}  // namespace ahd::bc6h

#else

namespace ahd::bc6h {
void floats_to_half_f16c(const float* in, uint16_t* out, int n) { floats_to_half_portable(in, out, n); }
}  // namespace ahd::bc6h

#endif
