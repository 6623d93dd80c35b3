// Size limits applied to untrusted files (containers, images, manifests) before anything is
// allocated, so a small hostile file cannot make us allocate or zero gigabytes.
#pragma once
#include <cstdint>
#include <string>

namespace ahd {

// The default largest width and height of one level: 16384, the D3D11/Vulkan 2D limit, so at most
// 16384² texels per level (2 GiB as RGBA16F). set_max_image_size() overrides it for the process
// (the library reads no environment: the CLI sets it from AHDPACK_MAX_SIZE).
constexpr uint32_t kDefaultMaxImageSize = 16384;

// The limit in force: set_max_image_size's value, else the default.
uint32_t max_image_size();

// Overrides the limit for this process; 0 returns to the default.
void set_max_image_size(uint32_t size);

// Throws ahd::Error("<path>: <w>x<h> is over the size limit of NxN texels per level
// (AHDPACK_MAX_SIZE raises it)") when w or h exceeds max_image_size(), and "<path>: empty image
// (WxH)" when either is 0.
void check_image_size(const std::string& path, uint64_t width, uint64_t height);

// check_image_size, and the layers of an array level together within the same texel budget
// (max_image_size()²), so a claimed array cannot multiply the allocation.
void check_layered_size(const std::string& path, uint64_t width, uint64_t height, uint64_t layers);

}  // namespace ahd

namespace ahd {

// How many times its compressed size a stored image can plausibly decode to, by the codec that
// stores it: the ceiling of each codec's own format, so a real file never exceeds it, while a
// small file whose header claims a huge image (a 300-byte PNG "of" 16384² texels) is refused
// before anything is allocated. Deflate (zip/zips/PNG/pxr24) cannot exceed 1032:1 (a run of 258
// bytes costs at least 2 bits); run-length codes (EXR rle, TGA, Radiance HDR) repeat at most 128
// values per 2-byte packet; B44/B44A store 16 halves (32 bytes) in 3 bytes at best; PIZ's Huffman
// repeats at most 255 values per ~9-bit code (~450:1); uncompressed data is 1:1. DWAA/DWAB (lossy
// DCT) can code a flat 8x8 block as one deflated DC value, so they get 64 x 1032. The values below
// add a margin over each ceiling; unknown codecs get the deflate bound.
uint64_t max_expansion(const std::string& codec);

// The one check of a header's claim against the file behind it, made by every reader before it
// allocates for the pixels: width and height within the size limit (check_layered_size, with
// `layers` images of width x height), and width·height·layers·bytes_per_texel (the decoded size
// in the file's own sample types) at most max_expansion(codec) x file_bytes + 64 KiB (headers
// and the offset tables of tiny files). Throws ahd::Error("<path>: <cause>") naming the claim and
// the file's size. Pure arithmetic, no overflow (every product is checked).
void check_declared_image(const std::string& path, uint64_t width, uint64_t height, uint64_t layers,
                          uint64_t bytes_per_texel, uint64_t file_bytes, const std::string& codec);

// a·b, or throws ahd::Error("<path>: <what> overflows") when the product exceeds `limit`: the
// checked arithmetic for counts read from files or flags.
uint64_t checked_mul(const std::string& path, const std::string& what, uint64_t a, uint64_t b,
                     uint64_t limit = UINT64_MAX);

}  // namespace ahd
