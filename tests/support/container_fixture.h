// What the container tests share (tests/unit and tests/judges container_test.cpp): random
// textures of any format and a level-by-level comparison.
#pragma once
#include <gtest/gtest.h>
#include <random>
#include "containers/container.h"
#include "containers/dds.h"
#include "containers/ktx2.h"
#include "containers/sha256.h"
#include "core/error.h"
#include "codecs/pixel_format_table.h"

namespace ahd_fixture::container_fixture {

using namespace ::ahd;

inline Texture random_texture(PixelFormat f, uint32_t w, uint32_t h, size_t levels, uint32_t seed) {
  std::mt19937 rng(seed);
  Texture t;
  t.format = f;
  for (size_t l = 0; l < levels; ++l) {
    TextureLevel lv;
    lv.width = std::max(1u, w >> l);
    lv.height = std::max(1u, h >> l);
    lv.data.resize(level_size_bytes(f, lv.width, lv.height));
    for (auto& b : lv.data) b = uint8_t(rng());
    t.levels.push_back(std::move(lv));
  }
  t.metadata = {{"ahd.plane", "iz"}, {"ahd.dz_min", "0.05"}};
  return t;
}

inline void expect_same_levels(const Texture& a, const Texture& b) {
  ASSERT_EQ(a.format, b.format);
  ASSERT_EQ(a.levels.size(), b.levels.size());
  for (size_t l = 0; l < a.levels.size(); ++l) {
    EXPECT_EQ(a.levels[l].width, b.levels[l].width);
    EXPECT_EQ(a.levels[l].height, b.levels[l].height);
    EXPECT_EQ(a.levels[l].data, b.levels[l].data) << "level " << l;
  }
}

inline uint32_t rd32(const std::vector<uint8_t>& b, size_t at) {
  return uint32_t(b[at]) | uint32_t(b[at + 1]) << 8 | uint32_t(b[at + 2]) << 16 | uint32_t(b[at + 3]) << 24;
}
inline uint64_t rd64(const std::vector<uint8_t>& b, size_t at) { return rd32(b, at) | uint64_t(rd32(b, at + 4)) << 32; }
inline void wr32(std::vector<uint8_t>& b, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + i] = uint8_t(v >> (8 * i));
}

}  // namespace ahd_fixture::container_fixture
