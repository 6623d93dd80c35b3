// Plain-data images passed between pipeline stages. No behaviour beyond indexing.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/large_buffer.h"

namespace ahd {

// A w×h image of `channels` floats per texel, row-major, top row first.
struct ImageF {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<float> data;  // width*height*channels

  ImageF() = default;
  ImageF(int w, int h, int c) : width(w), height(h), channels(c) { assign_large(data, size_t(w) * h * c, 0.0f); }
  size_t texels() const { return size_t(width) * height; }
  float* at(int x, int y) { return data.data() + (size_t(y) * width + x) * channels; }
  const float* at(int x, int y) const { return data.data() + (size_t(y) * width + x) * channels; }
};

// A w×h image of `channels` bytes per texel (UNORM8 data), row-major, top row first.
struct Image8 {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<uint8_t> data;

  Image8() = default;
  Image8(int w, int h, int c) : width(w), height(h), channels(c) { assign_large(data, size_t(w) * h * c, uint8_t(0)); }
  uint8_t* at(int x, int y) { return data.data() + (size_t(y) * width + x) * channels; }
  const uint8_t* at(int x, int y) const { return data.data() + (size_t(y) * width + x) * channels; }
};

}  // namespace ahd
