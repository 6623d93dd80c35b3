// What the shader-snippet tests share: the snippets' sources, HLSL taken to GLSL by real HLSL tools,
// and a full-screen program around a fragment main(). Needs a current GL context (gl_context.h).
#pragma once
#include <string>

#include "gl_context.h"

namespace ahd_test {

// A file's whole text; empty when it cannot be read.
std::string read_text(const std::string& path);

// The GLSL 330 fragment source: formats/shaders/ahd_decode.glsl followed by `glsl_main`; or, with
// `hlsl`, ahd_decode.hlsl followed by `hlsl_main`, compiled by glslang's HLSL front end to SPIR-V
// and taken back to GLSL 330 by spirv-cross. Empty (and a test failure recorded) when a tool fails.
std::string decode_fragment(bool hlsl, const char* glsl_main, const char* hlsl_main);

// A linked program of a full-screen triangle (three vertices from gl_VertexID) and `fragment`,
// made current. Records a test failure (with the log) when a stage does not compile or link.
GLuint full_screen_program(const std::string& fragment);

}  // namespace ahd_test
