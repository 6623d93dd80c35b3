// Uploads one of our textures (any PixelFormat, compressed ones included) to GL as it is,
// with bilinear filtering and clamp-to-edge: what an engine would do with the bytes.
#pragma once
#include "core/texture.h"
#include "gl_context.h"

namespace ahd_test {

// Returns the GL texture name (0 and a GL error on failure). Uploads level `level` only.
GLuint upload_texture(const ahd::Texture& t, size_t level = 0);

}  // namespace ahd_test
