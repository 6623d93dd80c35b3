#include "gl_upload.h"

#include "codecs/pixel_format_table.h"

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
    const ahd::PixelFormatRow& row = ahd::pixel_format_row(t.format);  // its upload format and type
    const GLenum format = row.gl_format, type = row.gl_type;
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
