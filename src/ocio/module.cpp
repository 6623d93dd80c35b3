// libahd_ocio.so: OpenColorIO's processors for ahdpack, loaded with dlopen only when an input is in
// another colour space than the working one (src/image/ocio_module.h). Plain calls, no ahdpack
// state: which transform and every check stay in image/colour_space.cpp.
#include <OpenColorIO/OpenColorIO.h>

#include "image/ocio_module.h"

namespace OCIO = OCIO_NAMESPACE;

namespace {

using ahd::OcioStep;

OCIO::TransformRcPtr transform_of(const OcioStep& s) {
  switch (s.kind) {
    case OcioStep::kBuiltin: {
      OCIO::BuiltinTransformRcPtr t = OCIO::BuiltinTransform::Create();
      t->setStyle(s.style.c_str());
      return t;
    }
    case OcioStep::kExponentWithLinear: {
      OCIO::ExponentWithLinearTransformRcPtr t = OCIO::ExponentWithLinearTransform::Create();
      t->setGamma(s.gamma);
      t->setOffset(s.offset);
      return t;
    }
    case OcioStep::kMatrix:
    default: {
      OCIO::MatrixTransformRcPtr t = OCIO::MatrixTransform::Create();
      t->setMatrix(s.matrix);
      return t;
    }
  }
}

const void* processor(const std::vector<OcioStep>& steps, std::string* err) {
  try {
    OCIO::TransformRcPtr t;
    if (steps.size() == 1) {
      t = transform_of(steps[0]);
    } else {
      OCIO::GroupTransformRcPtr g = OCIO::GroupTransform::Create();
      for (const OcioStep& s : steps) g->appendTransform(transform_of(s));
      t = g;
    }
    const OCIO::ConstCPUProcessorRcPtr cpu = OCIO::Config::CreateRaw()->getProcessor(t)->getOptimizedCPUProcessor(
        OCIO::BIT_DEPTH_F32, OCIO::BIT_DEPTH_F32, OCIO::OPTIMIZATION_NONE);
    return new OCIO::ConstCPUProcessorRcPtr(cpu);
  } catch (const std::exception& e) {
    *err = e.what();
  } catch (...) {
    *err = "unknown error";
  }
  return nullptr;
}

void apply_rgb(const void* p, float* rgb, size_t count) {
  const OCIO::ConstCPUProcessorRcPtr& cpu = *static_cast<const OCIO::ConstCPUProcessorRcPtr*>(p);
  for (size_t i = 0; i < count; ++i) cpu->applyRGB(rgb + i * 3);
}

void release(const void* p) { delete static_cast<const OCIO::ConstCPUProcessorRcPtr*>(p); }

const ahd::OcioModule kModule = {ahd::kOcioModuleAbi, processor, apply_rgb, release};

}  // namespace

// The module's one exported symbol (GetProcAddress finds only exported names on Windows).
#if defined(_WIN32)
#define AHD_OCIO_EXPORT __declspec(dllexport)
#else
#define AHD_OCIO_EXPORT __attribute__((visibility("default")))
#endif
extern "C" AHD_OCIO_EXPORT const void* ahd_ocio_module() { return &kModule; }
