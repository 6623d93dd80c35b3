// The smaller direction and ratio planes (issue 43, "dir_ratio_scale"), sampled by a real GL —
// Mesa's llvmpipe, bilinear, clamp to edge — with the I_z texture's UV at every full-res texel
// centre: what it returns is what decode_planes (pipeline/plane_decode.cpp) computes, so every
// error ahdpack reports for these profiles is the error an engine sees. Two uploads: the decoded
// planes as 32-bit float textures (GL filters them in float: positions, weights and clamping must
// agree to float precision), and the BC5/BC4 files as they are (llvmpipe filters 8-bit texels into
// 8-bit results: within two UNORM8 steps).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "files/profile_file.h"
#include "gl_fixture.h"
#include "gl_shader.h"
#include "gl_upload.h"
#include "pipeline/convert.h"
#include "sample/analytic_baker.h"

using namespace ahd;
using namespace ahd_test;

namespace {

const char* kSampleFragment = R"(#version 330 core
uniform sampler2D t_dir;
uniform sampler2D t_ratio;
uniform vec2 grid;
out vec4 frag;
void main() {
  vec2 tc = gl_FragCoord.xy / grid;  // the full-res texel centre's normalised UV
  frag = vec4(texture(t_dir, tc).rg, texture(t_ratio, tc).r, 0.0);
})";

// A float texture of a decoded plane's first `channels` channels (1 or 2), bilinear, clamp to edge.
GLuint upload_float(const ImageF& img, int channels) {
  std::vector<float> data(img.texels() * size_t(channels));
  for (size_t i = 0; i < img.texels(); ++i)
    for (int c = 0; c < channels; ++c) data[i * size_t(channels) + size_t(c)] = img.data[i * size_t(img.channels) + size_t(c)];
  GLuint t;
  glGenTextures(1, &t);
  glBindTexture(GL_TEXTURE_2D, t);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, channels == 2 ? GL_RG32F : GL_R32F, img.width, img.height, 0,
               channels == 2 ? GL_RG : GL_RED, GL_FLOAT, data.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return t;
}

}  // namespace

class LowResSampling : public GlTest {};

TEST_F(LowResSampling, GlSamplesTheSmallPlanesAsDecodePlanesDoes) {
  for (const std::string name : {"pc-bc-half", "pc-bc-quarter"}) {
    SCOPED_TRACE(name);
    BakerOptions bo;
    bo.width = 20, bo.height = 12;  // divisible by 2 and 4: bilinear weights exact in 8 bits
    const PipelineResult r = run_conversion(bake_analytic_scene(bo), load_profile(name), PipelineOptions{});
    const Plane *dir = nullptr, *ratio = nullptr;
    for (const Plane& p : r.planes) {
      if (p.name == "dir") dir = &p;
      if (p.name == "ratio") ratio = &p;
    }
    ASSERT_TRUE(dir && ratio);
    ASSERT_LT(dir->texture.levels[0].width, 20u);
    const GLuint prog = full_screen_program(kSampleFragment);
    GLuint fbo_tex, fbo, vao;
    glGenTextures(1, &fbo_tex);
    glBindTexture(GL_TEXTURE_2D, fbo_tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, bo.width, bo.height, 0, GL_RGBA, GL_FLOAT, nullptr);
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, fbo_tex, 0);
    ASSERT_EQ(glCheckFramebufferStatus(GL_FRAMEBUFFER), GLenum(GL_FRAMEBUFFER_COMPLETE));
    glViewport(0, 0, bo.width, bo.height);
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glUniform1i(glGetUniformLocation(prog, "t_dir"), 0);
    glUniform1i(glGetUniformLocation(prog, "t_ratio"), 1);
    glUniform2f(glGetUniformLocation(prog, "grid"), float(bo.width), float(bo.height));
    const DecodedPlanes dec = decode_planes(r.planes, false, 0);
    const ImageF dir_f = decode_plane(dir->texture.format, dir->texture.levels[0]);
    const ImageF ratio_f = decode_plane(ratio->texture.format, ratio->texture.levels[0]);
    for (const bool as_float : {true, false}) {
      glActiveTexture(GL_TEXTURE0);
      const GLuint td = as_float ? upload_float(dir_f, 2) : upload_texture(dir->texture);
      glActiveTexture(GL_TEXTURE1);
      const GLuint tr = as_float ? upload_float(ratio_f, 1) : upload_texture(ratio->texture);
      ASSERT_EQ(glGetError(), GLenum(GL_NO_ERROR));
      glDrawArrays(GL_TRIANGLES, 0, 3);
      std::vector<float> px(size_t(bo.width) * bo.height * 4);
      glPixelStorei(GL_PACK_ALIGNMENT, 1);
      glReadPixels(0, 0, bo.width, bo.height, GL_RGBA, GL_FLOAT, px.data());
      ASSERT_EQ(glGetError(), GLenum(GL_NO_ERROR));
      // GL's row j is texture t = (j + 0.5) / height: our row j (no flip on upload, as engines do).
      double max_ratio = 0, max_uv = 0;
      for (int j = 0; j < bo.height; ++j)
        for (int i = 0; i < bo.width; ++i) {
          const size_t o = (size_t(j) * bo.width + i) * 4, t = size_t(j) * bo.width + i;
          max_ratio = std::max(max_ratio, std::fabs(double(px[o + 2]) - dec.ratio[t * 3]));
          float d[3];
          unit_uv_to_dir(&px[o], d);
          for (int c = 0; c < 3; ++c) max_uv = std::max(max_uv, std::fabs(double(d[c]) - dec.d[t * 3 + c]));
        }
      std::printf("%s, %s upload: GL vs decode_planes at the texel centres: ratio %.2e, direction %.2e\n",
                  name.c_str(), as_float ? "float" : "BC5/BC4", max_ratio, max_uv);
      if (as_float) {
        EXPECT_LT(max_ratio, 1e-6);
        EXPECT_LT(max_uv, 1e-5);
      } else {
        EXPECT_LT(max_ratio, 2.0 / 255.0);
      }
      for (GLuint t : {td, tr}) glDeleteTextures(1, &t);
    }
    glDeleteTextures(1, &fbo_tex);
    glDeleteFramebuffers(1, &fbo);
    glDeleteVertexArrays(1, &vao);
    glDeleteProgram(prog);
  }
}
