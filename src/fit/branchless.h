// Branch-free forms of the clamps the refined fit runs on every evaluation: on random lighting the
// branches GCC emits for std::max / std::min / ternaries here mispredict often. Each returns the
// very value of the expression it names (NaN and signed zeros included), so outputs keep their bytes.
#pragma once
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace ahd {

// std::max(0.0, x): x > 0 ? x : +0 (NaN → 0). maxsd(x, 0) is exactly that.
inline double positive_part(double x) {
#if defined(__SSE2__)
  return _mm_cvtsd_f64(_mm_max_sd(_mm_set_sd(x), _mm_setzero_pd()));
#else
  return x > 0.0 ? x : 0.0;
#endif
}

// a < b ? a : b (b when either is NaN or they are equal). minsd(a, b) is exactly that.
inline double less_or_second(double a, double b) {
#if defined(__SSE2__)
  return _mm_cvtsd_f64(_mm_min_sd(_mm_set_sd(a), _mm_set_sd(b)));
#else
  return a < b ? a : b;
#endif
}

// x > y ? a : b (b when either of x, y is NaN), by a compare mask.
inline double select_greater(double x, double y, double a, double b) {
#if defined(__SSE2__)
  const __m128d m = _mm_cmpgt_sd(_mm_set_sd(x), _mm_set_sd(y));
  return _mm_cvtsd_f64(_mm_or_pd(_mm_and_pd(m, _mm_set_sd(a)), _mm_andnot_pd(m, _mm_set_sd(b))));
#else
  return x > y ? a : b;
#endif
}

}  // namespace ahd
