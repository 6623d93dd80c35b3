#include "gl_context.h"

#include <GL/osmesa.h>

#include <cstring>
#include <vector>

namespace ahd_test {

bool ensure_gl_context(std::string* why) {
  static OSMesaContext ctx = nullptr;
  static std::vector<float> buffer(64 * 64 * 4);
  if (!ctx) {
    const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 0,
                           OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION, 3, OSMESA_CONTEXT_MINOR_VERSION, 3, 0};
    ctx = OSMesaCreateContextAttribs(attribs, nullptr);
    if (!ctx) {
      if (why) *why = "OSMesaCreateContextAttribs failed";
      return false;
    }
  }
  if (!OSMesaMakeCurrent(ctx, buffer.data(), GL_FLOAT, 64, 64)) {
    if (why) *why = "OSMesaMakeCurrent failed";
    return false;
  }
  return true;
}

bool has_gl_extension(const char* name) {
  GLint n = 0;
  glGetIntegerv(GL_NUM_EXTENSIONS, &n);
  for (GLint i = 0; i < n; ++i) {
    const char* e = reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, GLuint(i)));
    if (e && std::strcmp(e, name) == 0) return true;
  }
  return false;
}

}  // namespace ahd_test
