// An off-screen OpenGL context on Mesa's software rasteriser (OSMesa, llvmpipe): the independent
// judge for our block codecs and shaders. One context per test process, made current on first use.
#pragma once
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>

#include <string>

namespace ahd_test {

// Makes a GL context current on this thread (created once, 64x64 RGBA float framebuffer).
// Returns false, with a reason in *why, when OSMesa cannot make one.
bool ensure_gl_context(std::string* why);

// True when the current context advertises the extension (e.g. "GL_ARB_texture_compression_bptc").
bool has_gl_extension(const char* name);

}  // namespace ahd_test
