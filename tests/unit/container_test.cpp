// KTX2 and DDS: bit-exact round trips for every format, the bytes the specs fix, and strict
// refusal of malformed, truncated or absurd files (one ahd::Error each, never a crash).
#include <gtest/gtest.h>

#include <random>

#include "containers/container.h"
#include "containers/dds.h"
#include "containers/ktx2.h"
#include "containers/sha256.h"
#include "core/error.h"
#include "codecs/pixel_format_table.h"
#include "container_fixture.h"

using namespace ahd;
using namespace ahd_fixture::container_fixture;

// Every row of the registry, in each container its row names (and refused by the others).
TEST(Container, RoundTripEveryFormatBothContainers) {
  for (const PixelFormatRow& row : pixel_format_rows())
    for (auto [w, h, levels] : {std::tuple{13u, 7u, 4u}, {16u, 16u, 5u}, {1u, 1u, 1u}, {5u, 3u, 1u}}) {
      const PixelFormat f = row.info.format;
      const Texture t = random_texture(f, w, h, levels, w * 31 + h);
      if (!(row.containers & kInKtx2)) {
        EXPECT_THROW(write_ktx2(t, {}), Error) << row.info.name;
      }
      if (!(row.containers & kInDds)) {
        EXPECT_THROW(write_dds(t), Error) << row.info.name;
      }
      for (bool zstd : {false, true}) {
        if (!(row.containers & kInKtx2)) break;
        const std::vector<uint8_t> k = write_ktx2(t, {zstd, 9});
        const Texture back = read_ktx2(k.data(), k.size(), "t.ktx2");
        expect_same_levels(t, back);
        // Metadata: ours plus KTXwriter/KTXorientation, sorted by key.
        bool found = false;
        for (const auto& [key, v] : back.metadata) found |= key == "ahd.plane" && v == "iz";
        EXPECT_TRUE(found);
        EXPECT_EQ(back.metadata.front().first, "KTXorientation");
      }
      if (!(row.containers & kInDds)) continue;
      const std::vector<uint8_t> d = write_dds(t);
      expect_same_levels(t, read_dds(d.data(), d.size(), "t.dds"));
    }
}

TEST(Container, Ktx2HeaderAndLevelLayoutFollowTheSpec) {
  const Texture t = random_texture(PixelFormat::BC6H_UFLOAT, 13, 7, 4, 1);
  const std::vector<uint8_t> b = write_ktx2(t);
  const uint8_t id[12] = {0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
  EXPECT_TRUE(std::equal(id, id + 12, b.begin()));
  EXPECT_EQ(rd32(b, 12), 143u);  // VK_FORMAT_BC6H_UFLOAT_BLOCK
  EXPECT_EQ(rd32(b, 16), 1u);    // typeSize
  EXPECT_EQ(rd32(b, 20), 13u);
  EXPECT_EQ(rd32(b, 24), 7u);
  EXPECT_EQ(rd32(b, 36), 1u);    // faceCount
  EXPECT_EQ(rd32(b, 40), 4u);    // levelCount
  // Levels are stored smallest first, each at a 16-byte-aligned offset (lcm(16, 4)).
  uint64_t prev = ~0ull;
  for (int l = 0; l < 4; ++l) {
    const uint64_t off = rd64(b, 80 + 24 * l), len = rd64(b, 80 + 24 * l + 8);
    EXPECT_EQ(off % 16, 0u);
    EXPECT_EQ(len, level_size_bytes(PixelFormat::BC6H_UFLOAT, std::max(1u, 13u >> l), std::max(1u, 7u >> l)));
    EXPECT_LT(off, prev) << "level " << l << " must come before the larger levels";
    prev = off;
  }
  // DFD: BC6H colour model 133, 4x4 texel block stored as 3,3.
  const uint32_t dfd = rd32(b, 48);
  EXPECT_EQ(rd32(b, dfd + 12) & 0xFF, 133u);
  EXPECT_EQ(rd32(b, dfd + 16), 0x0303u);
  // RGBA16F: typeSize 2, 8-byte alignment.
  const std::vector<uint8_t> h = write_ktx2(random_texture(PixelFormat::RGBA16_SFLOAT, 3, 3, 2, 2));
  EXPECT_EQ(rd32(h, 16), 2u);
  EXPECT_EQ(rd64(h, 80) % 8, 0u);
}

TEST(Container, DdsHeaderFollowsTheDocs) {
  const Texture t = random_texture(PixelFormat::BC6H_UFLOAT, 9, 5, 3, 3);
  const std::vector<uint8_t> b = write_dds(t);
  EXPECT_EQ(rd32(b, 0), 0x20534444u);  // "DDS "
  EXPECT_EQ(rd32(b, 4), 124u);
  EXPECT_EQ(rd32(b, 12), 5u);          // height
  EXPECT_EQ(rd32(b, 16), 9u);          // width
  EXPECT_EQ(rd32(b, 20), 3u * 2u * 16u);  // linear size of level 0: 3×2 blocks of 16 bytes
  EXPECT_EQ(rd32(b, 28), 3u);          // mip count
  EXPECT_EQ(rd32(b, 84), 0x30315844u);  // "DX10"
  EXPECT_EQ(rd32(b, 128), 95u);        // DXGI_FORMAT_BC6H_UF16
  EXPECT_EQ(rd32(b, 132), 3u);         // TEXTURE2D
  EXPECT_EQ(rd32(b, 140), 1u);         // arraySize
  EXPECT_EQ(b.size(), 148u + 96u + 16u + 16u);  // 3x2, 1x1 and 1x1 blocks
  const std::vector<uint8_t> u = write_dds(random_texture(PixelFormat::RGBA16_SFLOAT, 7, 3, 1, 4));
  EXPECT_EQ(rd32(u, 20), 7u * 8u);  // row pitch for uncompressed formats
  // Legacy headers where they are exact: BC5 as FourCC "BC5U" with no DX10 extension.
  const std::vector<uint8_t> l = write_dds(random_texture(PixelFormat::BC5_UNORM, 8, 8, 1, 5));
  EXPECT_EQ(rd32(l, 84), 0x55354342u);  // "BC5U"
  EXPECT_EQ(l.size(), 128u + 4 * 16);
}

TEST(Container, TruncationAtEveryByteIsRefused) {
  for (bool zstd : {false, true}) {
    const std::vector<uint8_t> k = write_ktx2(random_texture(PixelFormat::RG8_UNORM, 6, 5, 3, 5), {zstd, 3});
    for (size_t n = 0; n < k.size(); ++n) EXPECT_THROW(read_ktx2(k.data(), n, "t.ktx2"), Error) << "KTX2 cut at " << n;
  }
  const std::vector<uint8_t> d = write_dds(random_texture(PixelFormat::RG8_UNORM, 6, 5, 3, 5));
  for (size_t n = 0; n < d.size(); ++n) EXPECT_THROW(read_dds(d.data(), n, "t.dds"), Error) << "DDS cut at " << n;
}

TEST(Container, CorruptHeadersAreRefusedWithOneLine) {
  const std::vector<uint8_t> good = write_ktx2(random_texture(PixelFormat::RGBA8_UNORM, 8, 8, 4, 6));
  auto expect_refused = [](std::vector<uint8_t> b, const char* what) {
    try {
      read_ktx2(b.data(), b.size(), "bad.ktx2");
      ADD_FAILURE() << what << " was accepted";
    } catch (const Error& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.rfind("bad.ktx2: ", 0), 0u) << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
  };
  auto patched = [&](size_t at, uint32_t v) {
    std::vector<uint8_t> b = good;
    wr32(b, at, v);
    return b;
  };
  expect_refused(patched(0, 0), "bad identifier");
  expect_refused(patched(12, 9999), "unknown vkFormat");
  expect_refused(patched(20, 0x80000000u), "absurd width");
  expect_refused(patched(24, 0x80000000u), "absurd height");
  expect_refused(patched(40, 40), "levelCount 40");
  expect_refused(patched(44, 1), "BasisLZ supercompression");
  expect_refused(patched(48, 0xFFFFFF00u), "DFD offset beyond EOF");
  expect_refused(patched(80, 0xFFFFFF00u), "level offset beyond EOF");
  expect_refused(patched(96, 12345), "wrong uncompressed length");
  expect_refused(patched(rd32(good, 48) + 12, 133), "DFD of another format");
  // zstd garbage: valid header, level bytes replaced by noise.
  std::vector<uint8_t> z = write_ktx2(random_texture(PixelFormat::R8_UNORM, 16, 16, 1, 7), {true, 3});
  const uint64_t off = rd64(z, 80);
  for (size_t i = off; i < z.size(); ++i) z[i] = uint8_t(i * 37);
  expect_refused(z, "zstd garbage");

  std::vector<uint8_t> d = write_dds(random_texture(PixelFormat::BC6H_UFLOAT, 8, 8, 1, 8));
  wr32(d, 128, 98);  // BC7, which we do not read
  EXPECT_THROW(read_dds(d.data(), d.size(), "bad.dds"), Error);
  wr32(d, 128, 95);
  wr32(d, 132, 4);  // a 3D texture
  EXPECT_THROW(read_dds(d.data(), d.size(), "bad.dds"), Error);
  wr32(d, 132, 3);
  wr32(d, 16, 0x80000000u);
  EXPECT_THROW(read_dds(d.data(), d.size(), "bad.dds"), Error);
}

TEST(Container, KindFromPathAndMagic) {
  EXPECT_EQ(container_kind_from_path("a/b.KTX2"), ContainerKind::KTX2);
  EXPECT_EQ(container_kind_from_path("b.dds"), ContainerKind::DDS);
  EXPECT_THROW(container_kind_from_path("b.png"), Error);
}

// FIPS 180-4's examples, and the hardware path (SHA-NI, when this CPU has it) against the portable
// one on every length around the block and padding boundaries and on a large buffer.
TEST(ContainerTest, Sha256PathsAgree) {
  auto hex = [](const std::string& s, Sha256Path p) {
    return sha256_hex(reinterpret_cast<const uint8_t*>(s.data()), s.size(), p);
  };
  for (Sha256Path p : {Sha256Path::Best, Sha256Path::Portable}) {
    EXPECT_EQ(hex("", p), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    EXPECT_EQ(hex("abc", p), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    EXPECT_EQ(hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq", p),
              "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
    EXPECT_EQ(hex(std::string(1000000, 'a'), p), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
  }
  std::mt19937 rng(7);
  std::vector<uint8_t> data(3 << 20);
  for (uint8_t& b : data) b = uint8_t(rng());
  for (size_t n = 0; n <= 200; ++n)
    ASSERT_EQ(sha256_hex(data.data(), n, Sha256Path::Best), sha256_hex(data.data(), n, Sha256Path::Portable)) << n;
  EXPECT_EQ(sha256_hex(data.data(), data.size(), Sha256Path::Best),
            sha256_hex(data.data(), data.size(), Sha256Path::Portable));
  if (!sha256_hardware()) GTEST_SKIP() << "no SHA extensions on this CPU: only the portable path was compared";
}
