#include "gl_shader.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

namespace ahd_test {
namespace {

const char* kFullScreenVertex = R"(#version 330 core
void main() {
  vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
})";

// HLSL → SPIR-V (glslang's HLSL front end) → GLSL 330 (spirv-cross). Empty on failure (reported).
std::string hlsl_to_glsl(const std::string& hlsl) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("ahd_hlsl_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  { std::ofstream(dir / "decode.hlsl") << hlsl; }
  const std::string spv = (dir / "decode.spv").string(), log = (dir / "log.txt").string();
  const std::string cmd = "glslangValidator -D -V -S frag -e main -o '" + spv + "' '" + (dir / "decode.hlsl").string() +
                          "' > '" + log + "' 2>&1 && spirv-cross --version 330 --no-es --flatten-ubo '" + spv +
                          "' --output '" + (dir / "decode.glsl").string() + "' >> '" + log + "' 2>&1";
  const int rc = std::system(cmd.c_str());
  const std::string glsl = read_text((dir / "decode.glsl").string()), messages = read_text(log);
  fs::remove_all(dir);
  if (rc != 0) ADD_FAILURE() << "HLSL compile failed (glslang-tools and spirv-cross installed?):\n" << messages;
  return rc == 0 ? glsl : std::string();
}

GLuint compile(GLenum kind, const std::string& src) {
  GLuint s = glCreateShader(kind);
  const char* p = src.c_str();
  glShaderSource(s, 1, &p, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096];
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    ADD_FAILURE() << "shader compile failed: " << log;
  }
  return s;
}

}  // namespace

std::string read_text(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

std::string decode_fragment(bool hlsl, const char* glsl_main, const char* hlsl_main) {
  const std::string dir = std::string(AHD_SOURCE_DIR) + "/formats/shaders/";
  if (!hlsl) return "#version 330 core\n" + read_text(dir + "ahd_decode.glsl") + glsl_main;
  return hlsl_to_glsl(read_text(dir + "ahd_decode.hlsl") + hlsl_main);
}

GLuint full_screen_program(const std::string& fragment) {
  EXPECT_FALSE(fragment.empty());
  const GLuint prog = glCreateProgram();
  glAttachShader(prog, compile(GL_VERTEX_SHADER, kFullScreenVertex));
  glAttachShader(prog, compile(GL_FRAGMENT_SHADER, fragment));
  glLinkProgram(prog);
  GLint linked = 0;
  glGetProgramiv(prog, GL_LINK_STATUS, &linked);
  EXPECT_TRUE(linked);
  glUseProgram(prog);
  return prog;
}

}  // namespace ahd_test
