// OpenImageIO's DDS reader judges our DDS files. Container unit tests: tests/unit/container_test.cpp.
#include <gtest/gtest.h>

#include <random>

#include "containers/container.h"
#include "containers/dds.h"
#include "containers/ktx2.h"
#include "containers/sha256.h"
#include "core/error.h"
#include "codecs/pixel_format_table.h"

using namespace ahd;

namespace {

Texture random_texture(PixelFormat f, uint32_t w, uint32_t h, size_t levels, uint32_t seed) {
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

void expect_same_levels(const Texture& a, const Texture& b) {
  ASSERT_EQ(a.format, b.format);
  ASSERT_EQ(a.levels.size(), b.levels.size());
  for (size_t l = 0; l < a.levels.size(); ++l) {
    EXPECT_EQ(a.levels[l].width, b.levels[l].width);
    EXPECT_EQ(a.levels[l].height, b.levels[l].height);
    EXPECT_EQ(a.levels[l].data, b.levels[l].data) << "level " << l;
  }
}

uint32_t rd32(const std::vector<uint8_t>& b, size_t at) {
  return uint32_t(b[at]) | uint32_t(b[at + 1]) << 8 | uint32_t(b[at + 2]) << 16 | uint32_t(b[at + 3]) << 24;
}
uint64_t rd64(const std::vector<uint8_t>& b, size_t at) { return rd32(b, at) | uint64_t(rd32(b, at + 4)) << 32; }
void wr32(std::vector<uint8_t>& b, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + i] = uint8_t(v >> (8 * i));
}

}  // namespace


#include <OpenImageIO/imageio.h>

#include <filesystem>

#include "image/image_io.h"
#include "files/output_set.h"

// OpenImageIO (a reader we did not write) re-reads our DDS files where its DDS reader supports the
// format: OIIO 2.4 reads legacy BC4/BC5 and RGBA8; it does not read DX10-extended files (BC6H,
// float and packed formats), for which ktx-parse and Mesa are the independent checks.
TEST(Container, OpenImageIOReadsOurDds) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "ahd_dds_oiio";
  fs::create_directories(dir);
  Texture rgba = random_texture(PixelFormat::RGBA8_UNORM, 7, 5, 1, 9);
  write_file_atomic((dir / "rgba.dds").string(), write_dds(rgba));
  auto in = OIIO::ImageInput::open((dir / "rgba.dds").string());
  ASSERT_TRUE(in) << OIIO::geterror();
  EXPECT_EQ(in->spec().width, 7);
  EXPECT_EQ(in->spec().height, 5);
  ASSERT_EQ(in->spec().nchannels, 4);
  std::vector<uint8_t> px(7 * 5 * 4);
  ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT8, px.data()));
  EXPECT_EQ(px, rgba.levels[0].data);
  in.reset();
  for (PixelFormat f : {PixelFormat::BC4_UNORM, PixelFormat::BC5_UNORM}) {
    write_file_atomic((dir / "bc.dds").string(), write_dds(random_texture(f, 12, 8, 1, 10)));
    auto bc = OIIO::ImageInput::open((dir / "bc.dds").string());
    ASSERT_TRUE(bc) << OIIO::geterror();
    EXPECT_EQ(bc->spec().width, 12);
    EXPECT_EQ(bc->spec().nchannels, format_info(f).channels);
  }
  fs::remove_all(dir);
}
