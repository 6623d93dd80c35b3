// <ahd/sample.h>: the built-in sample for library consumers (C++ and C).
#include <ahd/sample.h>

#include <cstdlib>
#include <cstring>

#include "sample/analytic_baker.h"

namespace ahd {

ShImage bake_sample(int size, int order, unsigned seed, int threads) {
  if (size < 1 || size > 16384 || (order != 1 && order != 2)) throw Error("sample: size must be 1..16384, order 1 or 2");
  BakerOptions bo;
  bo.width = bo.height = size;
  bo.coeffs = order == 1 ? 4 : 9;
  bo.seed = seed;
  bo.threads = threads;
  return bake_analytic_scene(bo);
}

}  // namespace ahd

extern "C" {

int ahd_sample_bake(int size, int order, unsigned seed, float** sh, unsigned char** coverage) {
  if (!sh || !coverage) return 1;
  *sh = nullptr;
  *coverage = nullptr;
  try {
    const ahd::ShImage img = ahd::bake_sample(size, order, seed);
    *sh = static_cast<float*>(std::malloc(img.data.size() * sizeof(float)));
    *coverage = static_cast<unsigned char*>(std::malloc(img.coverage.size()));
    if (!*sh || !*coverage) {
      std::free(*sh), std::free(*coverage);
      *sh = nullptr, *coverage = nullptr;
      return 1;
    }
    std::memcpy(*sh, img.data.data(), img.data.size() * sizeof(float));
    std::memcpy(*coverage, img.coverage.data(), img.coverage.size());
    return 0;
  } catch (...) {
    return 1;
  }
}

void ahd_sample_free(void* p) { std::free(p); }

}  // extern "C"
