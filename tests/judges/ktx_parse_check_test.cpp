// Independent judge for our KTX2 files: ktx-parse (npm registry, a reader we did not write) must
// find the header, levels, DFD and key/values we meant, for every format, with and without zstd,
// single textures and arrays (atlas pages as layers).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>

#include "cli_runner.h"
#include "containers/ktx2.h"
#include "codecs/pixel_format_table.h"
#include "files/output_set.h"

namespace fs = std::filesystem;
using namespace ahd;

TEST(KtxParse, ReadsEveryFormatWeWrite) {
  const fs::path tools = fs::path(AHD_SOURCE_DIR) / "tests" / "tools";
  // A judge whose tool is missing skips (as PreviewChromium does): it checks our files, not the tool.
  if (std::system("command -v node >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "node is not installed (scripts/setup.sh installs it)";
  if (!fs::exists(tools / "node_modules" / "ktx-parse"))
    GTEST_SKIP() << "ktx-parse is not installed: run scripts/setup.sh (it runs npm ci in tests/tools)";
  const fs::path dir = ahd_test::temp_dir("ktxparse");
  std::mt19937 rng(42);
  int checked = 0;
  int want_checked = 0;
  for (const PixelFormatRow& row : pixel_format_rows()) {
    if (!(row.containers & kInKtx2)) continue;
    const PixelFormat f = row.info.format;
    want_checked += 4;
    for (int variant = 0; variant < 4; ++variant) {  // zstd or not × one layer or an array of 3 (atlas pages)
      const bool zstd = variant & 1;
      const uint32_t layers = variant & 2 ? 3 : 1;
      Texture t;
      t.format = f;
      t.layers = layers;
      for (uint32_t l = 0; l < 4; ++l) {
        TextureLevel lv{std::max(1u, 13u >> l), std::max(1u, 9u >> l), {}};
        lv.data.resize(layers * level_size_bytes(f, lv.width, lv.height));
        for (auto& b : lv.data) b = uint8_t(rng());
        t.levels.push_back(lv);
      }
      t.metadata = {{"ahd.plane", "dir"}, {"ahd.profile", "uncompressed"}};
      const std::string stem = std::string(format_info(f).name) + (zstd ? "_zstd" : "") + (layers > 1 ? "_array" : "");
      const fs::path file = dir / (stem + ".ktx2");
      write_file_atomic(file.string(), write_ktx2(t, {zstd, 9}));

      // What we meant, written independently of the writer's byte layout.
      const std::vector<uint32_t> dfd = ktx2_dfd(f);
      nlohmann::json want;
      want["vkFormat"] = format_info(f).vk_format;
      // KTX2 typeSize (KTX 2.0 spec, "typeSize"): 1 for block formats; the component's size when
      // the texel splits evenly into its channels (rgba16f 2); else the packed word (b10g11r11 4).
      const FormatInfo& info = format_info(f);
      const int type_size = info.is_compressed                          ? 1
                            : info.bytes_per_block % info.channels == 0 ? info.bytes_per_block / info.channels
                                                                        : info.bytes_per_block;
      want["typeSize"] = type_size;
      want["width"] = 13;
      want["height"] = 9;
      want["supercompression"] = zstd ? 2 : 0;
      want["layerCount"] = layers > 1 ? layers : 0;
      want["levels"] = nlohmann::json::array();
      for (size_t l = 0; l < t.levels.size(); ++l) {
        const fs::path raw = dir / (stem + ".level" + std::to_string(l) + ".bin");
        write_file_atomic(raw.string(), t.levels[l].data);
        want["levels"].push_back({{"bytes", t.levels[l].data.size()}, {"raw", raw.string()}});
      }
      const int block = format_info(f).block_width;
      want["dfd"] = {{"colorModel", row.ktx2.color_model},
                     {"texelBlockDimension", {block - 1, block - 1, 0, 0}},
                     {"bytesPlane0", format_info(f).bytes_per_block},
                     {"samples", nlohmann::json::array()}};
      for (size_t s = 7; s + 4 <= dfd.size(); s += 4)
        want["dfd"]["samples"].push_back({{"bitOffset", dfd[s] & 0xFFFF}, {"bitLength", (dfd[s] >> 16) & 0xFF},
                                          {"channelType", dfd[s] >> 24}, {"lower", dfd[s + 2]}, {"upper", dfd[s + 3]}});
      want["keyValue"] = {{"ahd.plane", "dir"}, {"ahd.profile", "uncompressed"}, {"KTXorientation", "rd"},
                          {"KTXwriter", "ahdpack " AHD_VERSION_STRING}};
      const fs::path exp = dir / (stem + ".json");
      write_file_atomic(exp.string(), want.dump());
      const std::string cmd = "node '" + (tools / "ktx_check.mjs").string() + "' '" + file.string() + "' '" + exp.string() + "' 2>&1";
      FILE* p = popen(cmd.c_str(), "r");
      ASSERT_NE(p, nullptr);
      std::string out;
      char buf[512];
      while (fgets(buf, sizeof buf, p)) out += buf;
      const int rc = pclose(p);
      EXPECT_EQ(rc, 0) << out;
      ++checked;
    }
  }
  EXPECT_EQ(checked, want_checked);
  EXPECT_GE(checked, 44);  // the eleven formats of 2026-12
  fs::remove_all(dir);
}
