/* The built-in sample lightmap (an analytic scene baked to SH), for tests, demos and consumers that
 * want to check they get the same bytes as `ahdpack convert` with no input. Link ahdpack::ahd_sample. */
#ifndef AHD_SAMPLE_H
#define AHD_SAMPLE_H
#include <stddef.h>

#include <ahd/export.h>

#ifdef __cplusplus
#include <ahd/types.h>

namespace ahd {
/* size×size texels, order 1 (L1) or 2 (L2), seed 0 = the canonical scene (what `ahdpack convert`
 * converts by default: size 256, order 2, seed 0). Deterministic whatever `threads` is. */
AHD_API ShImage bake_sample(int size = 256, int order = 2, unsigned seed = 0, int threads = 0);
}  // namespace ahd

extern "C" {
#endif

/* C form: allocates *sh (size*size*coeffs*3 floats) and *coverage (size*size bytes); release both
 * with ahd_sample_free. Returns 0 on success, non-zero on invalid arguments or no memory. */
AHD_API int ahd_sample_bake(int size, int order, unsigned seed, float** sh, unsigned char** coverage);
AHD_API void ahd_sample_free(void* p);

#ifdef __cplusplus
}
#endif
#endif /* AHD_SAMPLE_H */
