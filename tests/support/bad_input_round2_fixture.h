// What the second bad-input round's tests share (tests/unit and tests/integration bad_input_round2_test.cpp).
#pragma once
#include <gtest/gtest.h>
#include <OpenImageIO/deepdata.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>
#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <thread>
#include <tuple>
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include "expect_error.h"
#include "limited_run.h"
#include "fixture_writers.h"
#include "cli_runner.h"
#include "file_bytes.h"
#include "sanitized.h"
#include "containers/ktx2.h"
#include "containers/limits.h"
#include "core/texture.h"
#include "core/error.h"
#include "fit/fit_image.h"
#include "image/ahd_intermediate.h"
#include "bakers/baker_layout.h"
#include "image/colour_space.h"
#include "image/image_io.h"
#include "files/file_io.h"
#include "bakers/layout_detect.h"
#include "bakers/layout_pages.h"
#include "scene/mesh_io.h"
#include "scene/placement_io.h"
#include "files/profile_file.h"
#include "image/sh_exr.h"
#include "scene/lightmap_raster.h"
#include "pipeline/profile.h"
#include "sh/sh_image.h"

namespace ahd_fixture::bad_input_round2_fixture {

namespace fs = std::filesystem;
using namespace ::ahd;

using ahd_test::slurp;
using ahd_test::spit;
using ahd_test::gltf_triangle;
using ahd_test::rd64;
using ahd_test::wr64;


using ahd_test::expect_file_error;

// An EXR of w x h with the given channels (value `v` everywhere), zip, scanline.
inline void write_exr(const fs::path& p, int w, int h, const std::vector<std::string>& names, float v = 0.5f,
               OIIO::TypeDesc type = OIIO::TypeDesc::HALF) {
  OIIO::ImageSpec spec(w, h, int(names.size()), type);
  spec.channelnames = names;
  spec.attribute("compression", "zip");
  std::vector<float> px(size_t(w) * h * names.size(), v);
  auto out = OIIO::ImageOutput::create(p.string());
  ASSERT_TRUE(out && out->open(p.string(), spec) && out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
  out->close();
}

inline std::vector<std::string> sh_names(int coeffs) {
  std::vector<std::string> n;
  for (int k = 0; k < coeffs; ++k)
    for (const char* c : {"R", "G", "B"}) n.push_back("sh" + std::to_string(k) + "." + c);
  return n;
}

// Rewrites a one-chunk scanline EXR's dataWindow and displayWindow to (0,0)-(w-1,h-1) and grows
// its offset table to the chunk count that size needs (`chunks`; 0: scanline zip, 16 rows a chunk),
// every entry pointing at the one real chunk: a small file OpenEXR opens whose header claims a
// huge image, as the audit's 13.9 KB EXR did.
inline void claim_exr_size(const fs::path& p, int w, int h, size_t chunks = 0) {
  std::vector<uint8_t> b = slurp(p);
  for (const char* attr : {"dataWindow", "displayWindow"}) {
    const std::string key = std::string(attr) + '\0' + "box2i" + '\0';
    auto at = std::search(b.begin(), b.end(), key.begin(), key.end());
    ASSERT_NE(at, b.end()) << attr;
    const size_t box = size_t(at - b.begin()) + key.size() + 4;  // after the 4-byte attribute size
    const int32_t v[4] = {0, 0, w - 1, h - 1};
    std::memcpy(&b[box], v, 16);
  }
  // The header ends with a 0 byte before the offset table; the single entry holds the chunk's offset.
  uint64_t chunk = 0;
  size_t table = 0;
  for (size_t i = 8; i + 8 < b.size(); ++i) {
    uint64_t v;
    std::memcpy(&v, &b[i], 8);
    if (b[i - 1] == 0 && v == i + 8) {  // the entry that points just past itself
      table = i, chunk = v;
      break;
    }
  }
  ASSERT_GT(table, 0u) << "offset table not found";
  if (chunks == 0) chunks = size_t((h + 15) / 16);
  const uint64_t moved = table + chunks * 8;
  std::vector<uint8_t> out(b.begin(), b.begin() + long(table));
  for (size_t c = 0; c < chunks; ++c) {
    uint8_t e[8];
    std::memcpy(e, &moved, 8);
    out.insert(out.end(), e, e + 8);
  }
  out.insert(out.end(), b.begin() + long(chunk), b.end());
  spit(p, out);
}

inline uint32_t crc32(const uint8_t* p, size_t n) {
  uint32_t c = 0xFFFFFFFFu;
  for (size_t i = 0; i < n; ++i) {
    c ^= p[i];
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1)));
  }
  return ~c;
}

// A valid 4x4 PNG rewritten to claim w x h in its IHDR (CRC fixed, so libpng reads the header).
inline void write_png_claiming(const fs::path& p, uint32_t w, uint32_t h) {
  ImageF img(4, 4, 4);
  for (float& v : img.data) v = 0.25f;
  write_image(p.string(), img);
  std::vector<uint8_t> b = slurp(p);
  ASSERT_GT(b.size(), 33u);
  ASSERT_EQ(std::string(b.begin() + 12, b.begin() + 16), "IHDR");
  for (int i = 0; i < 4; ++i) b[16 + i] = uint8_t(w >> (24 - 8 * i)), b[20 + i] = uint8_t(h >> (24 - 8 * i));
  b[24] = 16;  // 16 bits a channel: the biggest claim a PNG can make per texel
  const uint32_t c = crc32(&b[12], 17);
  for (int i = 0; i < 4; ++i) b[29 + i] = uint8_t(c >> (24 - 8 * i));
  spit(p, b);
}

// A one-level intermediate of a w x h L1 image with valid fits; `edit` may change the spec and
// pixels (the ahd.flags channel, the attributes) before it is written back.
inline void write_intermediate_file(const fs::path& p, int w, int h,
                             const std::function<void(OIIO::ImageSpec&, std::vector<float>&)>& edit = {}) {
  FittedLevel l;
  l.sh = make_sh_image(w, h, 4);
  for (float& v : l.sh.data) v = 0.5f;
  std::fill(l.sh.coverage.begin(), l.sh.coverage.end(), uint8_t(1));
  l.ahd = make_ahd_image(w, h, false);
  for (size_t i = 0; i < l.sh.texels(); ++i) l.ahd.set_texel(i, AhdFit{{1, 1, 1}, {0, 0, 1}, {0.5f, 0.5f, 0.5f}, 0});
  l.ahd.coverage = l.sh.coverage;
  FitOptions fo;
  write_intermediate(p.string(), {l}, fo);
  if (!edit) return;
  auto in = OIIO::ImageInput::open(p.string());
  ASSERT_TRUE(in);
  OIIO::ImageSpec spec = in->spec();
  std::vector<float> px(size_t(spec.width) * spec.height * spec.nchannels);
  ASSERT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()));
  in->close();
  edit(spec, px);
  spec.set_format(OIIO::TypeDesc::FLOAT);
  auto out = OIIO::ImageOutput::create(p.string());
  ASSERT_TRUE(out && out->open(p.string(), spec) && out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
  out->close();
}

inline int channel_of(const OIIO::ImageSpec& spec, const std::string& name) {
  for (int c = 0; c < spec.nchannels; ++c)
    if (spec.channelnames[size_t(c)] == name) return c;
  return -1;
}


// A Godot LightmapGI set: base.exr (RGB, w x h) and base.exr.import with slices/vertical.
inline fs::path godot_set(const fs::path& d, int w, int h, int slices) {
  const fs::path exr = d / "lm.exr";
  write_exr(exr, w, h, {"R", "G", "B"});
  spit(d / "lm.exr.import", "[remap]\nimporter=\"2d_array_texture\"\n\n[params]\nslices/vertical=" +
                                std::to_string(slices) + "\nslices/horizontal=1\n");
  return exr;
}

}  // namespace ahd_fixture::bad_input_round2_fixture
