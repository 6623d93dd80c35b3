// The basic Data Format Descriptor of every format we write (Khronos Data Format Spec 1.3).
#include <cstring>

#include "containers/ktx2.h"

namespace ahd {
namespace {

constexpr uint32_t kModelRGBSDA = 1, kModelBC4 = 131, kModelBC5 = 132, kModelBC6H = 133;
constexpr uint32_t kPrimariesBT709 = 1, kTransferLinear = 1;
constexpr uint32_t kFloat = 0x80, kSigned = 0x40, kExponent = 0x20;
constexpr uint32_t kR = 0, kG = 1, kB = 2, kA = 15;
constexpr uint32_t kOne = 0x3F800000u, kMinusOne = 0xBF800000u;

struct Sample {
  uint32_t bit_offset, bit_length, channel, lower, upper;
};

std::vector<uint32_t> build(uint32_t model, uint32_t block_w, uint32_t block_h, uint32_t bytes_plane0,
                            const std::vector<Sample>& samples) {
  const uint32_t block_size = 24 + 16 * uint32_t(samples.size());
  std::vector<uint32_t> w;
  w.push_back(4 + block_size);                  // dfdTotalSize
  w.push_back(0);                               // vendorId 0 (Khronos), descriptorType 0 (basic)
  w.push_back(2u | block_size << 16);           // versionNumber 2 (spec 1.3), descriptorBlockSize
  w.push_back(model | kPrimariesBT709 << 8 | kTransferLinear << 16);  // flags 0: straight alpha
  w.push_back((block_w - 1) | (block_h - 1) << 8);                    // texelBlockDimension0..3
  w.push_back(bytes_plane0);                    // bytesPlane0..3
  w.push_back(0);                               // bytesPlane4..7
  for (const Sample& s : samples) {
    w.push_back(s.bit_offset | (s.bit_length - 1) << 16 | s.channel << 24);
    w.push_back(0);  // sample position 0,0,0,0
    w.push_back(s.lower);
    w.push_back(s.upper);
  }
  return w;
}

}  // namespace

std::vector<uint32_t> ktx2_dfd(PixelFormat f) {
  switch (f) {
    case PixelFormat::R8_UNORM:
      return build(kModelRGBSDA, 1, 1, 1, {{0, 8, kR, 0, 255}});
    case PixelFormat::RG8_UNORM:
      return build(kModelRGBSDA, 1, 1, 2, {{0, 8, kR, 0, 255}, {8, 8, kG, 0, 255}});
    case PixelFormat::RGBA8_UNORM:
      return build(kModelRGBSDA, 1, 1, 4, {{0, 8, kR, 0, 255}, {8, 8, kG, 0, 255}, {16, 8, kB, 0, 255}, {24, 8, kA, 0, 255}});
    case PixelFormat::RGBA16_SFLOAT: {
      const uint32_t t = kFloat | kSigned;
      return build(kModelRGBSDA, 1, 1, 8, {{0, 16, kR | t, kMinusOne, kOne}, {16, 16, kG | t, kMinusOne, kOne},
                                          {32, 16, kB | t, kMinusOne, kOne}, {48, 16, kA | t, kMinusOne, kOne}});
    }
    case PixelFormat::RGBA32_SFLOAT: {
      const uint32_t t = kFloat | kSigned;
      return build(kModelRGBSDA, 1, 1, 16, {{0, 32, kR | t, kMinusOne, kOne}, {32, 32, kG | t, kMinusOne, kOne},
                                           {64, 32, kB | t, kMinusOne, kOne}, {96, 32, kA | t, kMinusOne, kOne}});
    }
    case PixelFormat::B10G11R11_UFLOAT:
      return build(kModelRGBSDA, 1, 1, 4, {{0, 11, kR | kFloat, 0, kOne}, {11, 11, kG | kFloat, 0, kOne},
                                          {22, 10, kB | kFloat, 0, kOne}});
    case PixelFormat::E5B9G9R9_UFLOAT:
      // Each channel: a 9-bit mantissa and the shared 5-bit exponent (bias 15), as the spec lists.
      return build(kModelRGBSDA, 1, 1, 4, {{0, 9, kR, 0, 8448}, {27, 5, kR | kExponent, 15, 31},
                                          {9, 9, kG, 0, 8448}, {27, 5, kG | kExponent, 15, 31},
                                          {18, 9, kB, 0, 8448}, {27, 5, kB | kExponent, 15, 31}});
    case PixelFormat::BC4_UNORM:
      return build(kModelBC4, 4, 4, 8, {{0, 64, 0, 0, 0xFFFFFFFFu}});
    case PixelFormat::BC5_UNORM:
      return build(kModelBC5, 4, 4, 16, {{0, 64, kR, 0, 0xFFFFFFFFu}, {64, 64, kG, 0, 0xFFFFFFFFu}});
    case PixelFormat::BC6H_UFLOAT:
      return build(kModelBC6H, 4, 4, 16, {{0, 128, kFloat, 0, kOne}});
    case PixelFormat::BC6H_SFLOAT:
      return build(kModelBC6H, 4, 4, 16, {{0, 128, kFloat | kSigned, kMinusOne, kOne}});
  }
  return {};
}

}  // namespace ahd
