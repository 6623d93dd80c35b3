// OpenImageIO's DDS reader judges our DDS files. Container unit tests: tests/unit/container_test.cpp.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "containers/container.h"
#include "containers/dds.h"
#include "containers/ktx2.h"
#include "containers/sha256.h"
#include "core/error.h"
#include "codecs/pixel_format_table.h"
#include "container_fixture.h"
#include "files/output_set.h"
#include "image/image_io.h"

using namespace ahd;
using namespace ahd_fixture::container_fixture;

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
