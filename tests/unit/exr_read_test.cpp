// The EXR reader on OpenEXR directly (src/image/exr_read.cpp) against OpenImageIO's reading of the
// same files: the same channel names in the same order, the same header facts and bit-identical
// pixels, for half and float files, scanline and tiled, single and multi-part.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "core/cpu.h"
#include "core/error.h"
#include "image/exr_zip.h"
#include "image/image_io.h"
#include "test_data.h"

namespace {

namespace fs = std::filesystem;

// What OpenImageIO makes of `path`'s part: the reference.
struct OiioView {
  ahd::ImageFileInfo info;
  std::vector<float> px;
};

OiioView oiio_read(const std::string& path, int part) {
  OiioView v;
  auto in = OIIO::ImageInput::open(path);
  EXPECT_TRUE(in) << OIIO::geterror();
  if (!in) return v;
  for (int p = 0; in->seek_subimage(p, 0); ++p)
    v.info.parts.push_back(in->spec().get_string_attribute("oiio:subimagename"));
  EXPECT_TRUE(in->seek_subimage(part, 0));
  const OIIO::ImageSpec spec = in->spec();
  v.info.width = spec.width;
  v.info.height = spec.height;
  v.info.channel_names = spec.channelnames;
  v.info.color_space = spec.get_string_attribute("oiio:ColorSpace");
  if (const OIIO::ParamValue* c = spec.find_attribute("chromaticities")) {
    const float* f = static_cast<const float*>(c->data());
    v.info.chromaticities.assign(f, f + 8);
  }
  v.px.resize(size_t(spec.width) * spec.height * spec.nchannels);
  EXPECT_TRUE(in->read_image(part, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, v.px.data()));
  return v;
}

void expect_same_as_oiio(const std::string& path, int part = 0) {
  SCOPED_TRACE(path + " part " + std::to_string(part));
  const OiioView ref = oiio_read(path, part);
  ahd::ImageFileInfo info;
  const ahd::ImageF img = ahd::read_image(path, &info, part);
  EXPECT_EQ(info.width, ref.info.width);
  EXPECT_EQ(info.height, ref.info.height);
  EXPECT_EQ(info.channel_names, ref.info.channel_names);
  EXPECT_EQ(info.parts, ref.info.parts);
  EXPECT_EQ(info.color_space, ref.info.color_space);
  EXPECT_EQ(info.chromaticities, ref.info.chromaticities);
  EXPECT_TRUE(info.is_float);
  ASSERT_EQ(img.data.size(), ref.px.size());
  EXPECT_EQ(0, std::memcmp(img.data.data(), ref.px.data(), ref.px.size() * sizeof(float)));
  // The banded reader gives the same rows.
  std::vector<float> rows(ref.px.size());
  ahd::read_image_rows(path, part, nullptr, [&](int y0, int y1, const float* r) {
    std::memcpy(&rows[size_t(y0) * info.width * info.channel_names.size()], r,
                size_t(y1 - y0) * info.width * info.channel_names.size() * sizeof(float));
  });
  EXPECT_EQ(0, std::memcmp(rows.data(), ref.px.data(), ref.px.size() * sizeof(float)));
}

// A file with names OpenImageIO reorders (layers, lower case, A before R in the file's order), a
// data window off the origin, declared chromaticities, tiles and a second part.
std::string write_odd_exr(bool tiled, OIIO::TypeDesc type) {
  const std::string path = (fs::temp_directory_path() / ("ahd_exr_read_" + std::to_string(::getpid()) +
                                                         (tiled ? "_t" : "_s") + type.c_str() + ".exr"))
                               .string();
  auto out = OIIO::ImageOutput::create(path);
  const std::vector<std::string> names = {"A", "B", "G", "R", "alpha", "sh1.B", "sh1.G", "sh1.R", "coverage", "z.x"};
  OIIO::ImageSpec specs[2];
  for (int p = 0; p < 2; ++p) {
    OIIO::ImageSpec& s = specs[p];
    s = OIIO::ImageSpec(37 + p, 29, p == 0 ? int(names.size()) : 3, type);
    s.x = 5;
    s.y = -3;
    // Parts of one file share their display window (OpenEXR's rule); the data windows differ.
    s.full_x = 0, s.full_y = 0, s.full_width = 64, s.full_height = 40;
    s.channelnames = p == 0 ? names : std::vector<std::string>{"Y", "RY", "BY"};
    if (tiled) s.tile_width = s.tile_height = 16;
    s.attribute("compression", p == 0 ? "piz" : "zip");
    s.attribute("oiio:subimagename", p == 0 ? "main" : "second");
    const float chroma[8] = {0.64f, 0.33f, 0.3f, 0.6f, 0.15f, 0.06f, 0.3127f, 0.329f};
    s.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), chroma);
  }
  EXPECT_TRUE(out->open(path, 2, specs)) << out->geterror();
  for (int p = 0; p < 2; ++p) {
    if (p) EXPECT_TRUE(out->open(path, specs[p], OIIO::ImageOutput::AppendSubimage));
    std::vector<float> px(size_t(specs[p].width) * specs[p].height * specs[p].nchannels);
    for (size_t i = 0; i < px.size(); ++i) px[i] = float(i % 977) * 0.37f - 40.0f + float(p);
    EXPECT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data())) << out->geterror();
  }
  EXPECT_TRUE(out->close());
  return path;
}

TEST(ExrRead, RealBakesMatchOpenImageIO) {
  const fs::path ragdoll = ahd_test::test_data("bakes/godot-ragdoll-plain/ragdoll_physics.exr");
  const fs::path vermilion = ahd_test::test_data("bakes/godot42-vermilion/world.exr");
  AHD_REQUIRE_DATA(ragdoll);
  AHD_REQUIRE_DATA(vermilion);
  expect_same_as_oiio(ragdoll.string());
  expect_same_as_oiio(vermilion.string());
}

TEST(ExrRead, CanonicalShInputsMatchOpenImageIO) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(fs::path(AHD_SOURCE_DIR) / "golden" / "inputs"))
    if (e.path().extension() == ".exr") expect_same_as_oiio(e.path().string()), ++n;
  EXPECT_GT(n, 0);
}

TEST(ExrRead, ReorderedChannelsWindowsTilesAndPartsMatchOpenImageIO) {
  for (bool tiled : {false, true})
    for (OIIO::TypeDesc t : {OIIO::TypeDesc(OIIO::TypeDesc::HALF), OIIO::TypeDesc(OIIO::TypeDesc::FLOAT)}) {
      const std::string path = write_odd_exr(tiled, t);
      expect_same_as_oiio(path, 0);
      expect_same_as_oiio(path, 1);
      EXPECT_THROW(ahd::read_image_info(path, 2), ahd::Error);
      fs::remove(path);
    }
}

// read_image_info answers from the file's first 256 KB when the headers are within them, and from
// the whole file when they are not (a 300 KB header attribute): either way what OpenImageIO reads.
TEST(ExrRead, InfoOfLargeFilesFromTheirHeadMatchesOpenImageIO) {
  for (bool big_header : {false, true}) {
    const std::string path = (fs::temp_directory_path() / ("ahd_exr_info_" + std::to_string(::getpid()) +
                                                           (big_header ? "_h" : "") + ".exr"))
                                 .string();
    auto out = OIIO::ImageOutput::create(path);
    OIIO::ImageSpec specs[2];
    for (int p = 0; p < 2; ++p) {
      specs[p] = OIIO::ImageSpec(300 + p, 200, p == 0 ? 9 : 3, OIIO::TypeDesc::FLOAT);
      specs[p].channelnames = p == 0 ? std::vector<std::string>{"sh0.R", "sh0.G", "sh0.B", "sh1.R", "sh1.G", "sh1.B",
                                                                "sh2.R", "sh2.G", "sh2.B"}
                                     : std::vector<std::string>{"R", "G", "B"};
      specs[p].full_width = 301, specs[p].full_height = 200;  // parts share their display window
      specs[p].attribute("compression", "none");
      specs[p].attribute("oiio:subimagename", p == 0 ? "sh" : "rgb");
      if (big_header) specs[p].attribute("comments", std::string(300 << 10, 'x'));
    }
    ASSERT_TRUE(out->open(path, 2, specs)) << out->geterror();
    for (int p = 0; p < 2; ++p) {
      if (p) ASSERT_TRUE(out->open(path, specs[p], OIIO::ImageOutput::AppendSubimage));
      std::vector<float> px(size_t(specs[p].width) * specs[p].height * specs[p].nchannels, 0.5f);
      ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data())) << out->geterror();
    }
    ASSERT_TRUE(out->close());
    ASSERT_GT(fs::file_size(path), uintmax_t(1) << 20);
    for (int part : {0, 1}) {
      SCOPED_TRACE(path + " part " + std::to_string(part));
      const OiioView ref = oiio_read(path, part);
      const ahd::ImageFileInfo info = ahd::read_image_info(path, part);
      EXPECT_EQ(info.width, ref.info.width);
      EXPECT_EQ(info.height, ref.info.height);
      EXPECT_EQ(info.channel_names, ref.info.channel_names);
      EXPECT_EQ(info.parts, ref.info.parts);
      EXPECT_EQ(info.color_space, ref.info.color_space);
    }
    EXPECT_THROW(ahd::read_image_info(path, 2), ahd::Error);
    fs::remove(path);
  }
}

// ZIP and ZIPS chunks are inflated by libdeflate (image/exr_zip.h) where the build has it: every
// value the same as OpenEXR's own decoding (the path switched off) and OpenImageIO's, for half and
// float channels, a data window off the origin, heights that end inside a chunk and several bands.
// A damaged chunk gives the same outcome either way (the fast path hands it back to OpenEXR).
struct ReadOutcome {
  std::vector<float> px;
  std::string error;
};

ReadOutcome read_outcome(const std::string& path) {
  ReadOutcome r;
  try {
    ahd::ImageFileInfo info;
    ahd::read_image_rows(path, 0, &info, [&](int y0, int y1, const float* p) {  // in bands of 64 rows
      r.px.insert(r.px.end(), p, p + size_t(y1 - y0) * info.width * info.channel_names.size());
    });
    const ahd::ImageF img = ahd::read_image(path, nullptr, 0);
    r.px.insert(r.px.end(), img.data.begin(), img.data.end());
  } catch (const ahd::Error& e) {
    r.error = e.what();
  }
  return r;
}

TEST(ExrRead, ZipChunksDecodeAsOpenExrDecodesThem) {
  if (!ahd::exr_zip_available()) GTEST_SKIP() << "built without libdeflate: OpenEXR decodes ZIP chunks";
  int checked = 0;
  for (const char* codec : {"zip", "zips"})
    for (OIIO::TypeDesc t : {OIIO::TypeDesc(OIIO::TypeDesc::HALF), OIIO::TypeDesc(OIIO::TypeDesc::FLOAT)})
      for (int height : {1, 17, 150}) {
        const std::string path = (fs::temp_directory_path() / ("ahd_exr_zip_" + std::to_string(::getpid()) + "_" +
                                                               codec + t.c_str() + std::to_string(height) + ".exr"))
                                     .string();
        auto out = OIIO::ImageOutput::create(path);
        OIIO::ImageSpec spec(43, height, 5, t);
        spec.x = -7, spec.y = 11;
        spec.channelnames = {"sh1.R", "A", "sh0.G", "R", "coverage"};
        spec.attribute("compression", codec);
        std::vector<float> px(size_t(spec.width) * spec.height * spec.nchannels);
        for (size_t i = 0; i < px.size(); ++i) px[i] = std::sin(float(i) * 0.71f) * 300.0f + float(i % 13);
        ASSERT_TRUE(out->open(path, spec)) << out->geterror();
        ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data())) << out->geterror();
        ASSERT_TRUE(out->close());
        SCOPED_TRACE(path);
        expect_same_as_oiio(path);  // the fast path against OpenImageIO's reading
        const ReadOutcome fast = read_outcome(path);
        ahd::set_exr_zip_enabled(false);
        const ReadOutcome plain = read_outcome(path);
        ahd::set_exr_zip_enabled(true);
        EXPECT_TRUE(fast.error.empty()) << fast.error;
        ASSERT_EQ(fast.px.size(), plain.px.size());
        EXPECT_EQ(0, std::memcmp(fast.px.data(), plain.px.data(), fast.px.size() * sizeof(float)));
        // A damaged byte in the middle of the chunks: the same values or the same error either way.
        if (height == 150) {
          std::vector<char> bytes(size_t(fs::file_size(path)));
          {
            std::ifstream in(path, std::ios::binary);
            in.read(bytes.data(), std::streamsize(bytes.size()));
          }
          bytes[bytes.size() * 2 / 3] ^= 0x5a;
          const std::string bad = path + ".bad.exr";  // a name of its own (OpenImageIO caches by name)
          {
            std::ofstream o(bad, std::ios::binary);
            o.write(bytes.data(), std::streamsize(bytes.size()));
          }
          const ReadOutcome f2 = read_outcome(bad);
          ahd::set_exr_zip_enabled(false);
          const ReadOutcome p2 = read_outcome(bad);
          ahd::set_exr_zip_enabled(true);
          EXPECT_EQ(f2.error, p2.error);
          ASSERT_EQ(f2.px.size(), p2.px.size());
          EXPECT_EQ(0, std::memcmp(f2.px.data(), p2.px.data(), f2.px.size() * sizeof(float)));
          EXPECT_FALSE(f2.error.empty() && f2.px == fast.px) << "the damage changed nothing: not a test";
          fs::remove(bad);
        }
        fs::remove(path);
        ++checked;
      }
  EXPECT_EQ(checked, 12);
}

}  // namespace

namespace {

// exr_zip_unpack against the definition (OpenEXR's ZIP: running sums of the stored bytes minus
// 128, then the first half's bytes at even places and the second half's at odd ones), with SSE2
// and with the plain loops, at sizes around the sixteen-byte steps.
TEST(ExrZip, SimdAndPlainLoopsGiveTheSameBytes) {
  uint32_t seed = 12345;
  for (size_t size : {size_t(0), size_t(1), size_t(2), size_t(15), size_t(16), size_t(17), size_t(18), size_t(31),
                      size_t(32), size_t(33), size_t(34), size_t(63), size_t(100), size_t(1000), size_t(4097)}) {
    std::vector<uint8_t> stored(size);
    for (uint8_t& b : stored) b = uint8_t((seed = seed * 1664525u + 1013904223u) >> 24);
    std::vector<uint8_t> t = stored, ref(size);
    for (size_t i = 1; i < size; ++i) t[i] = uint8_t(t[i - 1] + t[i] - 128);
    for (size_t i = 0; i < size; ++i) ref[i] = i % 2 == 0 ? t[i / 2] : t[(size + 1) / 2 + i / 2];
    for (unsigned off : {0u, ahd::cpu::kAllSimd}) {
      SCOPED_TRACE("size " + std::to_string(size) + (off ? " plain loops" : " SIMD"));
      ahd::cpu::disable_for_tests(off);
      std::vector<uint8_t> work = stored, out(size, 0xee);
      ahd::exr_zip_unpack(work.data(), out.data(), size);
      ahd::cpu::disable_for_tests(0);
      EXPECT_EQ(out, ref);
    }
  }
}

}  // namespace
