// OpenColorIO behind dlopen: the colour-space conversions of image/colour_space.cpp (a declared
// space other than the working one, an sRGB-encoded plane) go through a small module
// (libahd_ocio.so, src/ocio/module.cpp) opened on first use, so a conversion of an input in the
// working space — nearly all of them — never loads OpenColorIO, yaml-cpp, expat and pystring
// (docs/performance-real.md "Process start"). The module only builds and runs OpenColorIO
// processors; which transform, every check and every message stay in colour_space.cpp. Internal
// to src/image.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

namespace ahd {

// Bumped whenever OcioModule or OcioStep changes: a module of another build is refused, not called.
constexpr int kOcioModuleAbi = 2;

// One transform of a chain, on OpenColorIO's raw config (no file, no environment variable read).
struct OcioStep {
  enum Kind { kBuiltin, kMatrix, kExponentWithLinear };
  Kind kind = kMatrix;
  std::string style;              // kBuiltin: a BuiltinTransform style
  double matrix[16] = {};         // kMatrix: MatrixTransform's 4×4, row-major
  double gamma[4] = {}, offset[4] = {};  // kExponentWithLinear (forward: encoded → linear)
};

// The module's calls. None throws.
struct OcioModule {
  int abi;
  // The F32 CPU processor (no optimisation) of `steps` in order: one step as it is, several as a
  // GroupTransform. Null with OpenColorIO's message in *err. Freed by release().
  const void* (*processor)(const std::vector<OcioStep>& steps, std::string* err);
  // Applies a processor to `count` RGB triples in place (applyRGB). Thread safe.
  void (*apply_rgb)(const void* processor, float* rgb, size_t count);
  // Frees a processor processor() built.
  void (*release)(const void* processor);
};

// The module, loaded on first call (thread safe), found as files/modules.h says. Throws
// ahd::Error("<why>: needs OpenColorIO, whose module cannot be loaded (<cause>)") when it is
// missing or of another build; `why` is the file (or option) that needed it.
const OcioModule& ocio_module(const std::string& why);

}  // namespace ahd
