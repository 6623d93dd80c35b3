// Shared by the fuzz targets: an ahd::Error is the expected answer to bad input; anything else
// (another exception, a crash, a sanitizer report) is a bug.
#pragma once
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>

#include "core/error.h"

namespace ahd_fuzz {

// Some readers take a path (OpenImageIO, Assimp, the layout loader): the input goes to a file of
// this process, named with `ext`.
inline std::string write_temp(const uint8_t* data, size_t size, const std::string& ext) {
  const std::string path = "/tmp/ahd_fuzz_" + std::to_string(::getpid()) + ext;
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) __builtin_trap();
  if (size) std::fwrite(data, 1, size, f);
  std::fclose(f);
  return path;
}

template <class Fn>
void expect_clean(Fn fn) {
  try {
    fn();
  } catch (const ahd::Error& e) {
    // The contract: one line.
    for (const char* c = e.what(); *c; ++c)
      if (*c == '\n') __builtin_trap();
  }
}

}  // namespace ahd_fuzz
