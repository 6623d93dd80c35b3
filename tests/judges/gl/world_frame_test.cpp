// World-space SH (Godot, Bakery, Unity): the stored direction lives in frame_from_normal(ng), and
// the shader snippets rebuild that frame from the geometric normal (ahd_to_frame). Issue 25: the
// encoder once chose the branch by copysign(1, n.z) and the shaders by ng.z >= 0.0, so a normal
// with z = -0.0 (every wall facing ±x in a Y-up engine can have it) decoded mirrored. Here a
// world-space analytic scene whose texels' normals are Y-up walls, Z-up walls and floors, at
// z = +0.0 and -0.0 and across z ≈ 0, is fitted by the library and decoded by the GLSL and HLSL
// snippets on Mesa; every texel must match the reference decoder (ahd_decode.h with the CPU frame)
// to 1e-4 relative, for the surface normal and for a tilted shading normal.
#include <gtest/gtest.h>

#include <cmath>

#include "codecs/octahedral.h"
#include "fit/ahd_decode.h"
#include "fit/fit_image.h"
#include "gl_shader.h"
#include "sh/sh.h"

using namespace ahd;
using namespace ahd_test;

namespace {

// Per texel (one pixel each): ng, the world shading normal, iz, (dir uv, ratio).
const char* kGlslMain = R"(
uniform sampler2D t_ng;
uniform sampler2D t_n;
uniform sampler2D t_iz;
uniform sampler2D t_dr;
uniform float dz_min;
out vec4 frag;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec3 ng = texelFetch(t_ng, p, 0).xyz;
  vec4 dr = texelFetch(t_dr, p, 0);
  vec3 n = ahd_to_frame(ng, texelFetch(t_n, p, 0).xyz);
  frag = vec4(ahd_irradiance(texelFetch(t_iz, p, 0).rgb, dr.rg, dr.bbb, n, dz_min), 1.0);
})";

const char* kHlslMain = R"(
Texture2D t_ng : register(t0);
Texture2D t_n : register(t1);
Texture2D t_iz : register(t2);
Texture2D t_dr : register(t3);
cbuffer Params : register(b0) { float4 p_dz; };
float4 main(float4 pos : SV_Position) : SV_Target {
  int3 p = int3(int2(pos.xy), 0);
  float3 ng = t_ng.Load(p).xyz;
  float4 dr = t_dr.Load(p);
  float3 n = ahd_to_frame(ng, t_n.Load(p).xyz);
  return float4(ahd_irradiance(t_iz.Load(p).rgb, dr.rg, dr.bbb, n, p_dz.x), 1.0);
})";

GLuint float_texture(const std::vector<float>& rgba, int w) {
  GLuint t;
  glGenTextures(1, &t);
  glBindTexture(GL_TEXTURE_2D, t);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, w, 1, 0, GL_RGBA, GL_FLOAT, rgba.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  return t;
}

void unit(double v[3]) {
  const double l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  for (int k = 0; k < 3; ++k) v[k] /= l;
}

// The geometric normals: Y-up walls (y = 0) and Z-up walls (z = ±0.0), floors, and z across 0.
std::vector<std::array<float, 3>> test_normals() {
  std::vector<std::array<float, 3>> ns;
  for (float zero : {0.0f, -0.0f})
    for (int a = 0; a < 8; ++a) {
      const double t = a * kPi / 4 + 0.1;
      ns.push_back({float(std::cos(t)), float(std::sin(t)), zero});  // Z-up walls
      ns.push_back({a & 1 ? -1.0f : 1.0f, 0.0f, zero});               // Y-up walls facing ±x
    }
  for (double z : {1e-7, 1e-5, 1e-3, 0.05, 0.3})
    for (double sign : {1.0, -1.0})
      for (int a = 0; a < 4; ++a) {
        const double t = a * kPi / 2 + 0.4, r = std::sqrt(1 - z * z);
        ns.push_back({float(r * std::cos(t)), float(r * std::sin(t)), float(sign * z)});
      }
  ns.push_back({0, 0, 1});
  ns.push_back({0, 0, -1});
  ns.push_back({0, 1, 0});  // a Y-up floor
  ns.push_back({0, -1, 0});
  return ns;
}

struct Result {
  double max_rel = 0;
  int texels = 0;
};

Result decode_on_gl(bool hlsl) {
  const auto ng = test_normals();
  const int n = int(ng.size()) * 2;  // each normal with the surface normal and a tilted shading normal
  // World-space L1 SH: light mostly from +y and +x (so a mirrored frame shows).
  ShImage sh;
  sh.width = n, sh.height = 1, sh.coeffs = 4;
  sh.data.assign(size_t(n) * 12, 0.0f);
  sh.coverage.assign(size_t(n), 1);
  sh.normals.resize(size_t(n) * 3);
  for (int i = 0; i < n; ++i) {
    float* t = sh.texel(size_t(i));
    for (int c = 0; c < 3; ++c) {
      t[0 * 3 + c] = 1.0f + 0.1f * c;
      t[1 * 3 + c] = 0.55f;   // y
      t[2 * 3 + c] = -0.15f;  // z
      t[3 * 3 + c] = 0.35f;   // x
    }
    for (int k = 0; k < 3; ++k) sh.normals[size_t(i) * 3 + k] = ng[size_t(i / 2)][size_t(k)];
  }
  FitOptions fo;
  const AhdImage ahd = fit_image(sh, fo, 1, nullptr);
  std::vector<float> t_ng, t_n, t_iz, t_dr;
  std::vector<double> want;
  for (int i = 0; i < n; ++i) {
    const auto& g = ng[size_t(i / 2)];
    double w[3] = {g[0], g[1], g[2]};
    if (i & 1) w[0] += 0.3, w[1] += 0.5, w[2] += 0.4, unit(w);
    const AhdFit f = ahd.texel(size_t(i));
    const double d[3] = {f.d[0], f.d[1], f.d[2]};
    double uv[2];
    hemi_oct_encode(d, uv);
    const float uv01[2] = {float(uv[0] * 0.5 + 0.5), float(uv[1] * 0.5 + 0.5)};
    // The reference: the stored direction as the shader reads it, the CPU frame.
    const double ruv[2] = {double(uv01[0]) * 2 - 1, double(uv01[1]) * 2 - 1};
    double dd[3];
    hemi_oct_decode(ruv, dd);
    const float df[3] = {float(dd[0]), float(dd[1]), float(dd[2])};
    const double gn[3] = {g[0], g[1], g[2]};
    double R[3][3];
    frame_from_normal(gn, R);
    double nl[3];
    for (int r = 0; r < 3; ++r) nl[r] = R[r][0] * w[0] + R[r][1] * w[1] + R[r][2] * w[2];
    double out[3];
    decode_irradiance(f.iz, df, f.ratio, nl, fo.dz_min, out);
    want.insert(want.end(), out, out + 3);
    t_ng.insert(t_ng.end(), {g[0], g[1], g[2], 0});
    t_n.insert(t_n.end(), {float(w[0]), float(w[1]), float(w[2]), 0});
    t_iz.insert(t_iz.end(), {f.iz[0], f.iz[1], f.iz[2], 0});
    t_dr.insert(t_dr.end(), {uv01[0], uv01[1], f.ratio[0], 0});
  }
  const GLuint prog = full_screen_program(decode_fragment(hlsl, kGlslMain, kHlslMain));
  const GLuint texs[4] = {float_texture(t_ng, n), float_texture(t_n, n), float_texture(t_iz, n), float_texture(t_dr, n)};
  // Bind by declaration order: samplers named t_ng, t_n, t_iz, t_dr (spirv-cross keeps the names
  // or flattens them to a combined sampler whose name contains them).
  const char* names[4] = {"t_ng", "t_n", "t_iz", "t_dr"};
  GLint count = 0;
  glGetProgramiv(prog, GL_ACTIVE_UNIFORMS, &count);
  for (GLint u = 0; u < count; ++u) {
    char name[256];
    GLint size;
    GLenum type;
    glGetActiveUniform(prog, GLuint(u), sizeof name, nullptr, &size, &type, name);
    const std::string s(name);
    const GLint loc = glGetUniformLocation(prog, name);
    for (int k = 3; k >= 0; --k)  // longest names first: "t_n" is a prefix of "t_ng"
      if (s.find(names[k]) != std::string::npos && (k != 1 || s.find("t_ng") == std::string::npos)) {
        glActiveTexture(GLenum(GL_TEXTURE0 + k));
        glBindTexture(GL_TEXTURE_2D, texs[k]);
        glUniform1i(loc, k);
        break;
      }
    if (s.find("dz") != std::string::npos) {
      if (type == GL_FLOAT_VEC4) glUniform4f(loc, float(fo.dz_min), 0, 0, 0);
      else glUniform1f(loc, float(fo.dz_min));
    }
  }
  GLuint fbo_tex, fbo, vao;
  glActiveTexture(GL_TEXTURE7);  // not one of the inputs' units
  glGenTextures(1, &fbo_tex);
  glBindTexture(GL_TEXTURE_2D, fbo_tex);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, n, 1, 0, GL_RGBA, GL_FLOAT, nullptr);
  glGenFramebuffers(1, &fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, fbo_tex, 0);
  glViewport(0, 0, n, 1);
  glGenVertexArrays(1, &vao);
  glBindVertexArray(vao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  std::vector<float> got(size_t(n) * 4);
  glReadPixels(0, 0, n, 1, GL_RGBA, GL_FLOAT, got.data());
  Result r;
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      const double ref = want[size_t(i) * 3 + c], g = got[size_t(i) * 4 + c];
      const double rel = std::fabs(g - ref) / std::max(std::fabs(ref), 1e-3);
      EXPECT_LT(rel, 1e-4) << (hlsl ? "HLSL" : "GLSL") << " texel " << i << " ng (" << ng[size_t(i / 2)][0] << ", "
                           << ng[size_t(i / 2)][1] << ", " << ng[size_t(i / 2)][2] << (std::signbit(ng[size_t(i / 2)][2]) ? " neg" : "")
                           << ") c " << c << ": shader " << g << " reference " << ref;
      r.max_rel = std::max(r.max_rel, rel);
    }
  r.texels = n;
  glDeleteFramebuffers(1, &fbo);
  glDeleteProgram(prog);
  return r;
}

class WorldFrame : public ::testing::TestWithParam<bool> {
 protected:
  void SetUp() override {
    std::string why;
    if (!ahd_test::ensure_gl_context(&why)) GTEST_SKIP() << why;
  }
};

}  // namespace

TEST(WorldFrameCpu, MinusZeroTakesThePlusBranchLikeTheShaders) {
  const double p[3] = {1, 0, 0.0}, m[3] = {1, 0, -0.0};
  double a[3][3], b[3][3];
  frame_from_normal(p, a);
  frame_from_normal(m, b);
  for (int i = 0; i < 2; ++i)  // tangent and bitangent: same bits (z differs only in the zero's sign)
    for (int j = 0; j < 3; ++j) EXPECT_EQ(a[i][j], b[i][j]) << i << " " << j;
}

TEST_P(WorldFrame, SnippetsDecodeWorldSpaceSceneLikeTheReferenceAtSignedZeroAndAcrossZ0) {
  const Result r = decode_on_gl(GetParam());
  std::printf("%s: %d texels (Y-up and Z-up walls at z = +0.0 and -0.0, floors, z across 0): max relative error vs the "
              "reference decoder %.2e\n",
              GetParam() ? "HLSL" : "GLSL", r.texels, r.max_rel);
  EXPECT_GT(r.texels, 80);
}

INSTANTIATE_TEST_SUITE_P(Lang, WorldFrame, ::testing::Values(false, true),
                         [](const auto& info) { return std::string(info.param ? "hlsl" : "glsl"); });
