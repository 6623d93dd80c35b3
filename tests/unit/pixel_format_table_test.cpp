// The registry of pixel formats (codecs/pixel_format_table.h): one row per format in enum order,
// codes that name one format each (0 names none), the spec numbers the files carry, and every
// row's codec and descriptor consistent with its facts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>

#include "containers/ktx2.h"
#include "core/error.h"
#include "codecs/pixel_format_table.h"
#include "pipeline/plane_codec.h"

using namespace ahd;

TEST(PixelFormatTable, OneRowPerFormatInOrderWithUniqueNamesAndCodes) {
  ASSERT_EQ(pixel_format_rows().size(), kPixelFormatCount);
  std::set<std::string> names;
  std::set<uint32_t> vks, dxgis;
  size_t i = 0;
  for (const PixelFormatRow& row : pixel_format_rows()) {
    EXPECT_EQ(size_t(row.info.format), i++);
    EXPECT_EQ(&format_info(row.info.format), &row.info);
    EXPECT_TRUE(names.insert(row.info.name).second) << row.info.name;
    PixelFormat f{};
    EXPECT_TRUE(format_from_name(row.info.name, &f) && f == row.info.format) << row.info.name;
    if (row.info.vk_format) {
      EXPECT_TRUE(vks.insert(row.info.vk_format).second) << row.info.name;
      EXPECT_TRUE(format_from_vk(row.info.vk_format, &f) && f == row.info.format) << row.info.name;
    }
    if (row.info.dxgi_format) {
      EXPECT_TRUE(dxgis.insert(row.info.dxgi_format).second) << row.info.name;
      EXPECT_TRUE(format_from_dxgi(row.info.dxgi_format, &f) && f == row.info.format) << row.info.name;
    }
  }
  EXPECT_THROW(format_info(PixelFormat::COUNT), Error);
}

// 0 is how a row says "no code" (VK_FORMAT_UNDEFINED, DXGI_FORMAT_UNKNOWN): it must name nothing,
// or a DDS with DXGI 0 would read as whichever format lacks a DXGI code.
TEST(PixelFormatTable, ZeroCodesNameNoFormat) {
  PixelFormat f = PixelFormat::BC6H_SFLOAT;
  EXPECT_FALSE(format_from_dxgi(0, &f));
  EXPECT_FALSE(format_from_vk(0, &f));
  EXPECT_FALSE(format_from_name("", &f));
  EXPECT_EQ(f, PixelFormat::BC6H_SFLOAT);  // untouched
}

// The numbers the files carry, from the specs (VkFormat in the Vulkan registry, DXGI_FORMAT in
// dxgiformat.h, the Khronos Data Format colour models), written here apart from the table.
TEST(PixelFormatTable, SpecNumbers) {
  struct Want {
    uint32_t vk, dxgi, model;
  };
  const std::map<std::string, Want> want = {
      {"r8", {9, 61, 1}},       {"rg8", {16, 49, 1}},        {"rgba8", {37, 28, 1}},          {"rgba16f", {97, 10, 1}},
      {"rgba32f", {109, 2, 1}}, {"b10g11r11", {122, 26, 1}}, {"rgb9e5", {123, 67, 1}},        {"bc4", {139, 80, 131}},
      {"bc5", {141, 83, 132}},  {"bc6h", {143, 95, 133}},    {"bc6h-signed", {144, 96, 133}},
  };
  size_t seen = 0;
  for (const PixelFormatRow& row : pixel_format_rows()) {
    const auto it = want.find(row.info.name);
    if (it == want.end()) continue;  // a format added later pins its numbers here when it can
    ++seen;
    EXPECT_EQ(row.info.vk_format, it->second.vk) << row.info.name;
    EXPECT_EQ(row.info.dxgi_format, it->second.dxgi) << row.info.name;
    EXPECT_EQ(row.ktx2.color_model, it->second.model) << row.info.name;
  }
  EXPECT_EQ(seen, want.size());
}

// The KTX2 descriptor built from a row says what the row's facts say: block size, bytes per
// block, and samples that cover the block's bits.
TEST(PixelFormatTable, DescriptorMatchesFacts) {
  for (const PixelFormatRow& row : pixel_format_rows()) {
    if (!(row.containers & kInKtx2)) continue;
    const std::vector<uint32_t> d = ktx2_dfd(row.info.format);
    ASSERT_EQ(d.size(), 7u + 4u * size_t(row.ktx2.sample_count)) << row.info.name;
    EXPECT_EQ(d[0], d.size() * 4) << row.info.name;
    EXPECT_EQ(d[3] & 0xFF, row.ktx2.color_model) << row.info.name;
    EXPECT_EQ(d[4], uint32_t(row.info.block_width - 1) | uint32_t(row.info.block_height - 1) << 8) << row.info.name;
    EXPECT_EQ(d[5], uint32_t(row.info.bytes_per_block)) << row.info.name;
    uint32_t bits_end = 0;
    for (size_t s = 7; s < d.size(); s += 4) bits_end = std::max(bits_end, (d[s] & 0xFFFF) + ((d[s] >> 16) & 0xFF) + 1);
    EXPECT_EQ(bits_end, uint32_t(row.info.bytes_per_block) * 8) << row.info.name;
  }
}

// Every row's codec: a flat image goes through encode and decode at the row's channel count and
// comes back within the format's precision (UNORM formats in [0,1], float formats HDR values).
TEST(PixelFormatTable, EveryCodecRoundTripsAFlatImage) {
  for (const PixelFormatRow& row : pixel_format_rows()) {
    const PixelFormat f = row.info.format;
    ASSERT_TRUE(plane_format_supported(f)) << row.info.name;
    ImageF img(9, 6, 4);
    const float v[4] = {row.info.is_float ? 3.5f : 0.75f, 0.5f, 0.25f, 1.0f};
    for (size_t i = 0; i < img.texels(); ++i)
      for (int c = 0; c < 4; ++c) img.data[i * 4 + c] = v[c];
    PlaneCodecStats st;
    const TextureLevel lvl = encode_plane(f, img, {}, &st);
    EXPECT_EQ(lvl.data.size(), level_size_bytes(f, 9, 6)) << row.info.name;
    EXPECT_EQ(st.clamped + st.non_finite, 0u) << row.info.name;
    const ImageF back = decode_plane(f, lvl);
    ASSERT_EQ(back.channels, row.info.channels) << row.info.name;
    ASSERT_EQ(back.texels(), img.texels()) << row.info.name;
    for (size_t i = 0; i < back.texels(); ++i)
      for (int c = 0; c < back.channels; ++c)
        ASSERT_NEAR(back.data[i * back.channels + c], v[c], 0.01f * v[c]) << row.info.name << " channel " << c;
  }
}
