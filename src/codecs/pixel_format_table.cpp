// The registry of pixel formats (codecs/pixel_format_table.h): one row per format, binding each
// format to its codec. It lives with the codecs so that core (the enum and FormatInfo,
// core/pixel_format.h) includes no codec: the rooms' includes stay acyclic.
#include "codecs/pixel_format_table.h"

#include <Imath/half.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>

#include "codecs/bc4.h"
#include "codecs/bc5.h"
#include "codecs/bc6h/bc6h_codec.h"
#include "codecs/bc6h/bc6h_fast.h"
#include "codecs/packed_float.h"
#include "core/error.h"

namespace ahd {
namespace {

// GL enums, spelled out so this file needs no GL header.
constexpr uint32_t GL_R8 = 0x8229, GL_RG8 = 0x822B, GL_RGBA8 = 0x8058, GL_RGBA16F = 0x881A, GL_RGBA32F = 0x8814,
                   GL_R11F_G11F_B10F = 0x8C3A, GL_RGB9_E5 = 0x8C3D, GL_COMPRESSED_RED_RGTC1 = 0x8DBB,
                   GL_COMPRESSED_RG_RGTC2 = 0x8DBD, GL_COMPRESSED_RGB_BPTC_SIGNED_FLOAT = 0x8E8E,
                   GL_COMPRESSED_RGB_BPTC_UNSIGNED_FLOAT = 0x8E8F;
constexpr uint32_t GL_RED = 0x1903, GL_RG = 0x8227, GL_RGB = 0x1907, GL_RGBA = 0x1908;
constexpr uint32_t GL_UNSIGNED_BYTE = 0x1401, GL_FLOAT = 0x1406, GL_HALF_FLOAT = 0x140B,
                   GL_UNSIGNED_INT_10F_11F_11F_REV = 0x8C3B, GL_UNSIGNED_INT_5_9_9_9_REV = 0x8C3E;

// KTX2 Data Format Descriptor values (Khronos Data Format Spec 1.3).
constexpr uint32_t kModelRGBSDA = 1, kModelBC4 = 131, kModelBC5 = 132, kModelBC6H = 133;
constexpr uint32_t kFloat = 0x80, kSigned = 0x40, kExponent = 0x20;
constexpr uint32_t kR = 0, kG = 1, kB = 2, kA = 15;
constexpr uint32_t kOne = 0x3F800000u, kMinusOne = 0xBF800000u;
constexpr uint32_t kSF = kFloat | kSigned;

constexpr uint32_t fourcc(char a, char b, char c, char d) {
  return uint32_t(uint8_t(a)) | uint32_t(uint8_t(b)) << 8 | uint32_t(uint8_t(c)) << 16 | uint32_t(uint8_t(d)) << 24;
}

constexpr uint8_t kBoth = kInKtx2 | kInDds;

// ---- The codecs' adapters: each row's encode/decode in the registry's signatures. ----

constexpr float kHalfMax = 65504.0f;

uint8_t to_unorm8(float v) {
  return uint8_t(std::lround(std::clamp(std::isfinite(v) ? v : 0.0f, 0.0f, 1.0f) * 255.0f));
}

// Channel c of texel i; channels the image lacks read as 0, alpha as 1.
float get(const ImageF& img, size_t i, int c) {
  if (c < img.channels) return img.data[i * img.channels + c];
  return c == 3 ? 1.0f : 0.0f;
}

template <int Ch>
void encode_unorm8(const ImageF& img, const CodecParams&, TextureLevel& lvl, CodecStats&) {
  const size_t n = img.texels();
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < Ch; ++c) lvl.data[i * Ch + c] = to_unorm8(get(img, i, c));
}

void decode_unorm8(const TextureLevel& lvl, ImageF& img) {
  const size_t n = img.texels() * size_t(img.channels);
  for (size_t i = 0; i < n; ++i) img.data[i] = lvl.data[i] / 255.0f;
}

// Sanitised (non-finite → 0 or ±max, beyond ±max → ±max) a row of texels at a time, then
// converted by bc6h::floats_to_half: F16C's eight floats an instruction where the CPU has it, the
// same bits as Imath::half's (test Bc6h.HalfConversionPathsGiveTheSameBits). One Imath::half at a
// time, this was 39.9 M instructions of a plain 512² conversion; now 15.4 M (callgrind).
void encode_rgba16f(const ImageF& img, const CodecParams&, TextureLevel& lvl, CodecStats& st) {
  uint16_t* out = reinterpret_cast<uint16_t*>(lvl.data.data());
  const size_t n = img.texels();
  constexpr size_t kRow = 512;
  float row[kRow * 4];
  for (size_t i0 = 0; i0 < n; i0 += kRow) {
    const size_t m = std::min(kRow, n - i0);
    for (size_t i = 0; i < m; ++i)
      for (int c = 0; c < 4; ++c) {
        float v = get(img, i0 + i, c);
        if (!std::isfinite(v)) {
          st.non_finite++;
          v = std::isnan(v) ? 0.0f : (v > 0 ? kHalfMax : -kHalfMax);
        } else if (std::fabs(v) > kHalfMax) {
          st.clamped++;
          v = std::copysign(kHalfMax, v);
        }
        row[i * 4 + c] = v;
      }
    bc6h::floats_to_half(row, out + i0 * 4, int(m * 4));
  }
}

void decode_rgba16f(const TextureLevel& lvl, ImageF& img) {
  const uint16_t* in = reinterpret_cast<const uint16_t*>(lvl.data.data());
  const size_t n = img.texels() * 4;
  for (size_t i = 0; i < n; ++i) {
    Imath::half h;
    h.setBits(in[i]);
    img.data[i] = float(h);
  }
}

void encode_rgba32f(const ImageF& img, const CodecParams&, TextureLevel& lvl, CodecStats&) {
  float* out = reinterpret_cast<float*>(lvl.data.data());
  const size_t n = img.texels();
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 4; ++c) out[i * 4 + c] = get(img, i, c);
}

void decode_rgba32f(const TextureLevel& lvl, ImageF& img) {
  std::memcpy(img.data.data(), lvl.data.data(), img.texels() * 16);
}

// The packed 32-bit HDR formats (codecs/packed_float.h).
template <uint32_t (*Pack)(float, float, float, PackStats*)>
void encode_packed(const ImageF& img, const CodecParams&, TextureLevel& lvl, CodecStats& st) {
  PackStats ps;
  const size_t n = img.texels();
  for (size_t i = 0; i < n; ++i) {
    const uint32_t v = Pack(get(img, i, 0), get(img, i, 1), get(img, i, 2), &ps);
    std::memcpy(&lvl.data[i * 4], &v, 4);
  }
  st.clamped += ps.negative + ps.too_large;
  st.non_finite += ps.non_finite;
}

template <void (*Unpack)(uint32_t, float*)>
void decode_packed(const TextureLevel& lvl, ImageF& img) {
  const size_t n = img.texels();
  for (size_t i = 0; i < n; ++i) {
    uint32_t v;
    std::memcpy(&v, &lvl.data[i * 4], 4);
    Unpack(v, &img.data[i * 3]);
  }
}

// BC4/BC5 keep their default search whatever the effort: mapping the effort onto their search
// would change the bytes of every non-default --quality conversion (a deliberate change for later).
void encode_bc4(const ImageF& img, const CodecParams& p, TextureLevel& lvl, CodecStats&) {
  lvl.data = bc4_encode_image(img, 0, p.threads);
}

void decode_bc4(const TextureLevel& lvl, ImageF& img) {
  bc4_decode_image(lvl.data.data(), img.width, img.height, 8, 0, img, 0);
}

void encode_bc5(const ImageF& img, const CodecParams& p, TextureLevel& lvl, CodecStats&) {
  lvl.data = bc5_encode_image(img, p.threads);
}

void decode_bc5(const TextureLevel& lvl, ImageF& img) {
  img = bc5_decode_image(lvl.data.data(), img.width, img.height);
}

// BC4 (one 8-byte half) and BC5 (two): texel t of each channel's BC4 block.
template <int Ch>
void decode_texel_bc45(const uint8_t* blk, int t, float* out) {
  float v[16];
  for (int c = 0; c < Ch; ++c) {
    bc4_decode_block(blk + 8 * c, v);
    out[c] = v[t];
  }
}

template <bool Signed>
void encode_bc6h(const ImageF& img, const CodecParams& p, TextureLevel& lvl, CodecStats& st) {
  Bc6hOptions o;
  o.is_signed = Signed;
  o.quality = Bc6hQuality(p.effort);
  o.threads = p.threads;
  Bc6hStats bs;
  lvl.data = bc6h_encode_image(img, o, &bs);
  st.clamped += bs.too_large + bs.negative;
  st.non_finite += bs.nan + bs.inf;
}

template <bool Signed>
void decode_bc6h(const TextureLevel& lvl, ImageF& img) {
  img = bc6h_decode_image(lvl.data.data(), img.width, img.height, Signed);
}

template <bool Signed>
void decode_texel_bc6h(const uint8_t* blk, int t, float* out) {
  uint16_t h[3];
  bc6h_decode_texel(blk, Signed, t, h);
  for (int c = 0; c < 3; ++c) {
    Imath::half v;
    v.setBits(h[c]);
    out[c] = float(v);
  }
}

// ---- The table. ----
// info: format, name, vkFormat, DXGI, GL internal format, block w, h, bytes per block, channels,
//       float, compressed.
// ktx2: typeSize, DFD colour model, samples {bit offset, bit length, channel | flags, lower, upper}.
// dds:  legacy FourCC written, FourCC also read, legacy RGB bits and masks.
// One row per format reads better than one member per line.
// clang-format off
constexpr PixelFormatRow kRows[] = {
    {.info = {PixelFormat::R8_UNORM, "r8", 9, 61, GL_R8, 1, 1, 1, 1, false, false},
     .ktx2 = {1, kModelRGBSDA, 1, {{0, 8, kR, 0, 255}}},
     .dds = {},
     .gl_format = GL_RED, .gl_type = GL_UNSIGNED_BYTE, .containers = kBoth,
     .encode = encode_unorm8<1>, .decode = decode_unorm8, .decode_texel = nullptr},
    {.info = {PixelFormat::RG8_UNORM, "rg8", 16, 49, GL_RG8, 1, 1, 2, 2, false, false},
     .ktx2 = {1, kModelRGBSDA, 2, {{0, 8, kR, 0, 255}, {8, 8, kG, 0, 255}}},
     .dds = {},
     .gl_format = GL_RG, .gl_type = GL_UNSIGNED_BYTE, .containers = kBoth,
     .encode = encode_unorm8<2>, .decode = decode_unorm8, .decode_texel = nullptr},
    {.info = {PixelFormat::RGBA8_UNORM, "rgba8", 37, 28, GL_RGBA8, 1, 1, 4, 4, false, false},
     .ktx2 = {1, kModelRGBSDA, 4, {{0, 8, kR, 0, 255}, {8, 8, kG, 0, 255}, {16, 8, kB, 0, 255}, {24, 8, kA, 0, 255}}},
     .dds = {.rgb_bits = 32, .masks = {0x000000FF, 0x0000FF00, 0x00FF0000, 0xFF000000}},
     .gl_format = GL_RGBA, .gl_type = GL_UNSIGNED_BYTE, .containers = kBoth,
     .encode = encode_unorm8<4>, .decode = decode_unorm8, .decode_texel = nullptr},
    {.info = {PixelFormat::RGBA16_SFLOAT, "rgba16f", 97, 10, GL_RGBA16F, 1, 1, 8, 4, true, false},
     .ktx2 = {2, kModelRGBSDA, 4, {{0, 16, kR | kSF, kMinusOne, kOne}, {16, 16, kG | kSF, kMinusOne, kOne},
                                   {32, 16, kB | kSF, kMinusOne, kOne}, {48, 16, kA | kSF, kMinusOne, kOne}}},
     .dds = {},
     .gl_format = GL_RGBA, .gl_type = GL_HALF_FLOAT, .containers = kBoth,
     .encode = encode_rgba16f, .decode = decode_rgba16f, .decode_texel = nullptr},
    {.info = {PixelFormat::RGBA32_SFLOAT, "rgba32f", 109, 2, GL_RGBA32F, 1, 1, 16, 4, true, false},
     .ktx2 = {4, kModelRGBSDA, 4, {{0, 32, kR | kSF, kMinusOne, kOne}, {32, 32, kG | kSF, kMinusOne, kOne},
                                   {64, 32, kB | kSF, kMinusOne, kOne}, {96, 32, kA | kSF, kMinusOne, kOne}}},
     .dds = {},
     .gl_format = GL_RGBA, .gl_type = GL_FLOAT, .containers = kBoth,
     .encode = encode_rgba32f, .decode = decode_rgba32f, .decode_texel = nullptr},
    // Vulkan B10G11R11_UFLOAT_PACK32 == DXGI R11G11B10_FLOAT (R in the low bits).
    {.info = {PixelFormat::B10G11R11_UFLOAT, "b10g11r11", 122, 26, GL_R11F_G11F_B10F, 1, 1, 4, 3, true, false},
     .ktx2 = {4, kModelRGBSDA, 3, {{0, 11, kR | kFloat, 0, kOne}, {11, 11, kG | kFloat, 0, kOne},
                                   {22, 10, kB | kFloat, 0, kOne}}},
     .dds = {},
     .gl_format = GL_RGB, .gl_type = GL_UNSIGNED_INT_10F_11F_11F_REV, .containers = kBoth,
     .encode = encode_packed<pack_b10g11r11>, .decode = decode_packed<unpack_b10g11r11>, .decode_texel = nullptr},
    // Vulkan E5B9G9R9_UFLOAT_PACK32 == DXGI R9G9B9E5_SHAREDEXP. The DFD gives each channel its
    // 9-bit mantissa and the shared 5-bit exponent (bias 15), as the spec lists.
    {.info = {PixelFormat::E5B9G9R9_UFLOAT, "rgb9e5", 123, 67, GL_RGB9_E5, 1, 1, 4, 3, true, false},
     .ktx2 = {4, kModelRGBSDA, 6, {{0, 9, kR, 0, 8448}, {27, 5, kR | kExponent, 15, 31},
                                   {9, 9, kG, 0, 8448}, {27, 5, kG | kExponent, 15, 31},
                                   {18, 9, kB, 0, 8448}, {27, 5, kB | kExponent, 15, 31}}},
     .dds = {},
     .gl_format = GL_RGB, .gl_type = GL_UNSIGNED_INT_5_9_9_9_REV, .containers = kBoth,
     .encode = encode_packed<pack_rgb9e5>, .decode = decode_packed<unpack_rgb9e5>, .decode_texel = nullptr},
    {.info = {PixelFormat::BC4_UNORM, "bc4", 139, 80, GL_COMPRESSED_RED_RGTC1, 4, 4, 8, 1, false, true},
     .ktx2 = {1, kModelBC4, 1, {{0, 64, 0, 0, 0xFFFFFFFFu}}},
     .dds = {.fourcc = fourcc('B', 'C', '4', 'U'), .fourcc_alt = fourcc('A', 'T', 'I', '1')},
     .gl_format = 0, .gl_type = 0, .containers = kBoth,
     .encode = encode_bc4, .decode = decode_bc4, .decode_texel = decode_texel_bc45<1>},
    {.info = {PixelFormat::BC5_UNORM, "bc5", 141, 83, GL_COMPRESSED_RG_RGTC2, 4, 4, 16, 2, false, true},
     .ktx2 = {1, kModelBC5, 2, {{0, 64, kR, 0, 0xFFFFFFFFu}, {64, 64, kG, 0, 0xFFFFFFFFu}}},
     .dds = {.fourcc = fourcc('B', 'C', '5', 'U'), .fourcc_alt = fourcc('A', 'T', 'I', '2')},
     .gl_format = 0, .gl_type = 0, .containers = kBoth,
     .encode = encode_bc5, .decode = decode_bc5, .decode_texel = decode_texel_bc45<2>},
    {.info = {PixelFormat::BC6H_UFLOAT, "bc6h", 143, 95, GL_COMPRESSED_RGB_BPTC_UNSIGNED_FLOAT, 4, 4, 16, 3, true, true},
     .ktx2 = {1, kModelBC6H, 1, {{0, 128, kFloat, 0, kOne}}},
     .dds = {},
     .gl_format = 0, .gl_type = 0, .containers = kBoth,
     .encode = encode_bc6h<false>, .decode = decode_bc6h<false>, .decode_texel = decode_texel_bc6h<false>},
    {.info = {PixelFormat::BC6H_SFLOAT, "bc6h-signed", 144, 96, GL_COMPRESSED_RGB_BPTC_SIGNED_FLOAT, 4, 4, 16, 3, true, true},
     .ktx2 = {1, kModelBC6H, 1, {{0, 128, kFloat | kSigned, kMinusOne, kOne}}},
     .dds = {},
     .gl_format = 0, .gl_type = 0, .containers = kBoth,
     .encode = encode_bc6h<true>, .decode = decode_bc6h<true>, .decode_texel = decode_texel_bc6h<true>},
};
// clang-format on

// One row per format, in enum order; facts every consumer relies on.
constexpr bool rows_well_formed() {
  for (size_t i = 0; i < std::size(kRows); ++i) {
    const PixelFormatRow& r = kRows[i];
    if (r.info.format != PixelFormat(i)) return false;
    if (r.info.block_width < 1 || r.info.block_height < 1 || r.info.bytes_per_block < 1) return false;
    if (r.info.channels < 1 || r.info.channels > 4) return false;
    if (r.info.is_compressed != (r.info.block_width > 1 || r.info.block_height > 1)) return false;
    if (r.ktx2.sample_count < 1 || r.ktx2.sample_count > kMaxKtx2Samples) return false;
    if ((r.containers & kInKtx2) && r.info.vk_format == 0) return false;   // KTX2 names a format by vkFormat
    if ((r.containers & kInDds) && r.info.dxgi_format == 0) return false;  // arrays need the DX10 header
    if (r.info.is_compressed == (r.gl_format != 0)) return false;
  }
  return true;
}
static_assert(std::size(kRows) == kPixelFormatCount, "one row per PixelFormat value: add the new format's row");
static_assert(rows_well_formed(), "rows must be in PixelFormat order, with consistent facts");

}  // namespace

const PixelFormatRow& pixel_format_row(PixelFormat f) {
  if (size_t(f) >= kPixelFormatCount) throw Error("invalid pixel format " + std::to_string(int(f)));
  return kRows[size_t(f)];
}

std::span<const PixelFormatRow> pixel_format_rows() { return kRows; }

}  // namespace ahd
