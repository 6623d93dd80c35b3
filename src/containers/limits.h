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
