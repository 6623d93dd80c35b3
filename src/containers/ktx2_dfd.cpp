// The basic Data Format Descriptor of every format we write (Khronos Data Format Spec 1.3), from
// the format's row (codecs/pixel_format_table.h: colour model and samples).
#include <cstring>

#include "containers/ktx2.h"
#include "codecs/pixel_format_table.h"

namespace ahd {
namespace {

constexpr uint32_t kPrimariesBT709 = 1, kTransferLinear = 1;

std::vector<uint32_t> build(uint32_t model, uint32_t block_w, uint32_t block_h, uint32_t bytes_plane0,
                            const std::vector<Ktx2Sample>& samples) {
  const uint32_t block_size = 24 + 16 * uint32_t(samples.size());
  std::vector<uint32_t> w;
  w.push_back(4 + block_size);                  // dfdTotalSize
  w.push_back(0);                               // vendorId 0 (Khronos), descriptorType 0 (basic)
  w.push_back(2u | block_size << 16);           // versionNumber 2 (spec 1.3), descriptorBlockSize
  w.push_back(model | kPrimariesBT709 << 8 | kTransferLinear << 16);  // flags 0: straight alpha
  w.push_back((block_w - 1) | (block_h - 1) << 8);                    // texelBlockDimension0..3
  w.push_back(bytes_plane0);                    // bytesPlane0..3
  w.push_back(0);                               // bytesPlane4..7
  for (const Ktx2Sample& s : samples) {
    w.push_back(s.bit_offset | (s.bit_length - 1) << 16 | s.channel << 24);
    w.push_back(0);  // sample position 0,0,0,0
    w.push_back(s.lower);
    w.push_back(s.upper);
  }
  return w;
}

}  // namespace

std::vector<uint32_t> ktx2_dfd(PixelFormat f) {
  const PixelFormatRow& row = pixel_format_row(f);
  const Ktx2Facts& k = row.ktx2;
  return build(k.color_model, uint32_t(row.info.block_width), uint32_t(row.info.block_height),
               uint32_t(row.info.bytes_per_block), {k.samples, k.samples + k.sample_count});
}

}  // namespace ahd
