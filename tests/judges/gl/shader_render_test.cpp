// The decode snippets run on a real GL — Mesa's llvmpipe — with hardware bilinear filtering of the
// produced textures, against the C++ reference decoder applied to bilinearly filtered plane values:
// the GLSL one (formats/shaders/ahd_decode.glsl) as it is, and the HLSL one
// (formats/shaders/ahd_decode.hlsl) compiled by a real HLSL front end (glslang, `glslangValidator -D`)
// to SPIR-V and taken back to GLSL by spirv-cross, so both snippets are proven against the reference.
// Also shows the paper's promise on a GPU pipeline: with the surface normal, the decoded irradiance
// is I_z, linear between texels.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "files/profile_file.h"
#include "codecs/octahedral.h"
#include "fit/ahd_decode.h"
#include "gl_shader.h"
#include "gl_upload.h"
#include "pipeline/convert.h"
#include "sample/analytic_baker.h"

using namespace ahd;
using namespace ahd_test;

namespace {

const char* kFragmentMain = R"(
uniform sampler2D t_iz;
uniform sampler2D t_dir;
uniform sampler2D t_ratio;
uniform int packed_planes;
uniform float dz_min;
uniform vec2 grid;
uniform vec3 normal;
uniform int mode;  // 0: decoded irradiance; 1: the filtered (duv, ratio); 2: the filtered iz
out vec4 frag;
void main() {
  vec2 tc = gl_FragCoord.xy / grid;
  vec3 iz = texture(t_iz, tc).rgb;
  vec2 duv;
  vec3 ratio;
  if (packed_planes != 0) {
    vec4 dr = texture(t_dir, tc);
    duv = dr.rg;
    ratio = dr.bbb;
  } else {
    duv = texture(t_dir, tc).rg;
    ratio = texture(t_ratio, tc).rrr;
  }
  if (mode == 1) frag = vec4(duv, ratio.r, 0.0);
  else if (mode == 2) frag = vec4(iz, 0.0);
  else frag = vec4(ahd_irradiance(iz, duv, ratio, normalize(normal), dz_min), iz.g);
})";

// The same main() in HLSL around the HLSL snippet. Parameters in one cbuffer (flattened by
// spirv-cross into `uniform vec4 Params[2]`), textures and one linear sampler.
const char* kHlslMain = R"(
Texture2D t_iz : register(t0);
Texture2D t_dir : register(t1);
Texture2D t_ratio : register(t2);
SamplerState s_linear : register(s0);
cbuffer Params : register(b0) {
  float4 p_grid_dzmin_mode;     // grid.xy, dz_min, mode
  float4 p_normal_packed;       // normal.xyz, packed planes
};
float4 main(float4 pos : SV_Position) : SV_Target {
  float2 tc = pos.xy / p_grid_dzmin_mode.xy;
  float3 iz = t_iz.Sample(s_linear, tc).rgb;
  float2 duv;
  float3 ratio;
  if (p_normal_packed.w != 0.0) {
    float4 dr = t_dir.Sample(s_linear, tc);
    duv = dr.rg;
    ratio = dr.bbb;
  } else {
    duv = t_dir.Sample(s_linear, tc).rg;
    ratio = t_ratio.Sample(s_linear, tc).rrr;
  }
  float mode = p_grid_dzmin_mode.w;
  if (mode == 1.0) return float4(duv, ratio.r, 0.0);
  if (mode == 2.0) return float4(iz, 0.0);
  return float4(ahd_irradiance(iz, duv, ratio, normalize(p_normal_packed.xyz), p_grid_dzmin_mode.z), iz.g);
})";

enum class Lang { Glsl, Hlsl };

// The location of the active uniform whose name contains `part` (spirv-cross names combined
// samplers SPIRV_Cross_Combined<texture><sampler>).
GLint uniform_containing(GLuint prog, const std::string& part) {
  GLint count = 0;
  glGetProgramiv(prog, GL_ACTIVE_UNIFORMS, &count);
  for (GLint i = 0; i < count; ++i) {
    char name[256];
    GLint size;
    GLenum type;
    glGetActiveUniform(prog, GLuint(i), sizeof name, nullptr, &size, &type, name);
    if (std::string(name).find(part) != std::string::npos) return glGetUniformLocation(prog, name);
  }
  return -1;
}

// Clamp-to-edge bilinear sample of a decoded plane at texture coordinate (s, t), as GL defines it.
void bilinear(const ImageF& img, double s, double t, float* out) {
  const double x = s * img.width - 0.5, y = t * img.height - 0.5;
  const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
  const double fx = x - x0, fy = y - y0;
  auto at = [&](int xi, int yi, int c) {
    xi = std::clamp(xi, 0, img.width - 1);
    yi = std::clamp(yi, 0, img.height - 1);
    return double(img.at(xi, yi)[c]);
  };
  for (int c = 0; c < img.channels; ++c)
    out[c] = float((1 - fx) * (1 - fy) * at(x0, y0, c) + fx * (1 - fy) * at(x0 + 1, y0, c) +
                   (1 - fx) * fy * at(x0, y0 + 1, c) + fx * fy * at(x0 + 1, y0 + 1, c));
}

struct RenderResult {
  double max_rel = 0;        // shader vs C++ reference on GL's filtered values, relative to magnitude
  double max_filter = 0;     // C++ reference on exact bilinear values vs shader (GL filter precision)
  double max_iz_linear = 0;  // with n = z: shader vs bilinear I_z (the paper's promise)
  int samples = 0;
};

RenderResult render_and_compare(Lang lang, const std::string& profile_name, const double normal[3]) {
  BakerOptions bo;
  bo.width = bo.height = 16;
  bo.area_samples = 4;
  const ShImage sh = bake_analytic_scene(bo);
  const Profile profile = load_profile(profile_name);
  PipelineOptions opt;
  opt.threads = 1;
  const PipelineResult r = run_conversion(sh, profile, opt);

  // GL program.
  const GLuint prog = full_screen_program(decode_fragment(lang == Lang::Hlsl, kFragmentMain, kHlslMain));

  const int G = 16 * 8;  // 8 × 8 sub-texel positions per texel
  GLuint fbo_tex, fbo, vao;
  glGenTextures(1, &fbo_tex);
  glBindTexture(GL_TEXTURE_2D, fbo_tex);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, G, G, 0, GL_RGBA, GL_FLOAT, nullptr);
  glGenFramebuffers(1, &fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, fbo_tex, 0);
  EXPECT_EQ(glCheckFramebufferStatus(GL_FRAMEBUFFER), GLenum(GL_FRAMEBUFFER_COMPLETE));
  glViewport(0, 0, G, G);
  glGenVertexArrays(1, &vao);
  glBindVertexArray(vao);

  const Plane* planes[3] = {nullptr, nullptr, nullptr};
  for (const Plane& p : r.planes) {
    if (p.name == "iz") planes[0] = &p;
    if (p.name == "dir" || p.name == "dirratio") planes[1] = &p;
    if (p.name == "ratio") planes[2] = &p;
  }
  GLuint texs[3] = {0, 0, 0};
  for (int i = 0; i < 3; ++i) {
    if (!planes[i]) continue;
    glActiveTexture(GL_TEXTURE0 + i);
    texs[i] = ahd_test::upload_texture(planes[i]->texture);
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR)) << "upload of " << planes[i]->name;
  }
  glUniform1i(uniform_containing(prog, "t_iz"), 0);
  glUniform1i(uniform_containing(prog, "t_dir"), 1);
  glUniform1i(uniform_containing(prog, "t_ratio"), planes[2] ? 2 : 1);
  auto set_parameters = [&](int mode) {
    if (lang == Lang::Hlsl) {
      const float params[8] = {float(G), float(G), float(opt.fit.dz_min), float(mode),
                               float(normal[0]), float(normal[1]), float(normal[2]), profile.packed_dir_ratio ? 1.0f : 0.0f};
      glUniform4fv(uniform_containing(prog, "Params"), 2, params);
      return;
    }
    glUniform1i(glGetUniformLocation(prog, "packed_planes"), profile.packed_dir_ratio ? 1 : 0);
    glUniform1f(glGetUniformLocation(prog, "dz_min"), float(opt.fit.dz_min));
    glUniform2f(glGetUniformLocation(prog, "grid"), float(G), float(G));
    glUniform3f(glGetUniformLocation(prog, "normal"), float(normal[0]), float(normal[1]), float(normal[2]));
    glUniform1i(glGetUniformLocation(prog, "mode"), mode);
  };
  auto draw = [&](int mode) {
    set_parameters(mode);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    std::vector<float> out(size_t(G) * G * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, G, G, GL_RGBA, GL_FLOAT, out.data());
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
    return out;
  };
  const std::vector<float> px = draw(0), raw_dr = draw(1), raw_iz = draw(2);

  // C++ reference on the decoded planes, filtered the same way.
  const ImageF iz = decode_plane(planes[0]->texture.format, planes[0]->texture.levels[0]);
  const ImageF dir = decode_plane(planes[1]->texture.format, planes[1]->texture.levels[0]);
  ImageF ratio = planes[2] ? decode_plane(planes[2]->texture.format, planes[2]->texture.levels[0]) : dir;
  RenderResult res;
  double nn[3] = {normal[0], normal[1], normal[2]};
  const double len = std::sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
  for (double& v : nn) v /= len;
  for (int j = 0; j < G; ++j)
    for (int i = 0; i < G; ++i) {
      const double s = (i + 0.5) / G, t = (j + 0.5) / G;
      const size_t o = (size_t(j) * G + i) * 4;
      auto reference = [&](const float* izv, const float* duv, float rr, double ref[3]) {
        const float rat[3] = {rr, rr, rr};
        const double uv[2] = {duv[0] * 2.0 - 1.0, duv[1] * 2.0 - 1.0};
        double d[3];
        hemi_oct_decode(uv, d);
        const float df[3] = {float(d[0]), float(d[1]), float(d[2])};
        decode_irradiance(izv, df, rat, nn, opt.fit.dz_min, ref);
      };
      const float* got = &px[o];
      // (a) the snippet's math: the C++ decoder on the values GL's sampler returned.
      double ref[3];
      reference(&raw_iz[o], &raw_dr[o], raw_dr[o + 2], ref);
      const double mag = std::max({std::fabs(ref[0]), std::fabs(ref[1]), std::fabs(ref[2]), 1e-3});
      for (int c = 0; c < 3; ++c) res.max_rel = std::max(res.max_rel, std::fabs(got[c] - ref[c]) / mag);
      // (b) GL's filtering against exact bilinear filtering of the decoded planes.
      float izv[4], dv[4], rv[4];
      bilinear(iz, s, t, izv);
      bilinear(dir, s, t, dv);
      bilinear(ratio, s, t, rv);
      double exact[3];
      reference(izv, dv, profile.packed_dir_ratio ? rv[2] : rv[0], exact);
      for (int c = 0; c < 3; ++c) res.max_filter = std::max(res.max_filter, std::fabs(got[c] - exact[c]) / mag);
      if (nn[2] > 0.999999) {
        const double izmag = std::max(double(izv[1]), 1e-3);
        res.max_iz_linear = std::max(res.max_iz_linear, std::fabs(got[1] - izv[1]) / izmag);
      }
      ++res.samples;
    }
  for (GLuint t : texs)
    if (t) glDeleteTextures(1, &t);
  glDeleteTextures(1, &fbo_tex);
  glDeleteFramebuffers(1, &fbo);
  glDeleteVertexArrays(1, &vao);
  glDeleteProgram(prog);
  return res;
}

}  // namespace

class ShaderRender : public ::testing::TestWithParam<std::tuple<Lang, std::string>> {
 protected:
  void SetUp() override {
    std::string why;
    if (!ahd_test::ensure_gl_context(&why)) GTEST_SKIP() << why;
  }
};

TEST_P(ShaderRender, SnippetMatchesReferenceDecoder) {
  const auto [lang, profile] = GetParam();
  const Profile p = load_profile(profile);
  for (PixelFormat f : {p.iz, p.dir, p.ratio, p.dirratio})
    if (!plane_format_supported(f)) GTEST_SKIP() << "profile " << profile << " needs " << format_info(f).name;
  const double z[3] = {0, 0, 1}, tilted[3] = {0.45, -0.3, 0.84};
  const RenderResult a = render_and_compare(lang, profile, z);
  const RenderResult b = render_and_compare(lang, profile, tilted);
  ASSERT_GT(a.samples, 0);
  std::printf("%s %s (%d samples per normal): snippet vs C++ on GL-filtered values: n=z %.2e, tilted %.2e; "
              "I_z linearity (n=z) %.2e; vs exact bilinear filtering: n=z %.2e, tilted %.2e\n",
              lang == Lang::Glsl ? "GLSL" : "HLSL", profile.c_str(), a.samples, a.max_rel, b.max_rel, a.max_iz_linear, a.max_filter, b.max_filter);
  // The snippet computes what the reference decoder computes, to float precision.
  EXPECT_LT(a.max_rel, 1e-5);
  EXPECT_LT(b.max_rel, 1e-5);
  // With the surface normal, the decoded irradiance IS the filtered I_z: linear between texels,
  // within half-float precision (2^-11) of exact bilinear interpolation.
  EXPECT_LT(a.max_iz_linear, 1e-3);
  // llvmpipe filters UNORM8 planes with 8-bit weights; a tilted normal sees that through d.
  EXPECT_LT(b.max_filter, 5e-2);
}

INSTANTIATE_TEST_SUITE_P(Profiles, ShaderRender,
                         ::testing::Combine(::testing::Values(Lang::Glsl, Lang::Hlsl),
                                            ::testing::Values("uncompressed", "pc-bc", "packed-float", "packed-rgb9e5")),
                         [](const auto& info) {
                           std::string n = std::string(std::get<0>(info.param) == Lang::Glsl ? "glsl_" : "hlsl_") +
                                           std::get<1>(info.param);
                           for (char& c : n)
                             if (c == '-') c = '_';
                           return n;
                         });
