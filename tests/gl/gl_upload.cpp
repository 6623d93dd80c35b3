#include "gl_upload.h"

namespace ahd_test {

GLuint upload_texture(const ahd::Texture& t, size_t level) {
  const ahd::FormatInfo& fi = ahd::format_info(t.format);
  const ahd::TextureLevel& l = t.levels.at(level);
  GLuint tex = 0;
  glGenTextures(1, &tex);
  glBindTexture(GL_TEXTURE_2D, tex);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  if (fi.is_compressed) {
    glCompressedTexImage2D(GL_TEXTURE_2D, 0, fi.gl_internal, GLsizei(l.width), GLsizei(l.height), 0,
                           GLsizei(l.data.size()), l.data.data());
  } else {
    GLenum format = GL_RGBA, type = GL_UNSIGNED_BYTE;
    switch (t.format) {
      case ahd::PixelFormat::R8_UNORM: format = GL_RED; break;
      case ahd::PixelFormat::RG8_UNORM: format = GL_RG; break;
      case ahd::PixelFormat::RGBA8_UNORM: break;
      case ahd::PixelFormat::RGBA16_SFLOAT: type = GL_HALF_FLOAT; break;
      case ahd::PixelFormat::RGBA32_SFLOAT: type = GL_FLOAT; break;
      case ahd::PixelFormat::B10G11R11_UFLOAT: format = GL_RGB, type = GL_UNSIGNED_INT_10F_11F_11F_REV; break;
      case ahd::PixelFormat::E5B9G9R9_UFLOAT: format = GL_RGB, type = GL_UNSIGNED_INT_5_9_9_9_REV; break;
      default: break;
    }
    glTexImage2D(GL_TEXTURE_2D, 0, GLint(fi.gl_internal), GLsizei(l.width), GLsizei(l.height), 0, format, type,
                 l.data.data());
  }
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, 0);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
  return tex;
}

}  // namespace ahd_test
