// Size limits applied to untrusted files (containers, images, manifests) before anything is
// allocated, so a small hostile file cannot make us allocate or zero gigabytes.
#pragma once
#include <cstdint>
#include <string>

namespace ahd {

// The default largest width and height of one level: 16384, the D3D11/Vulkan 2D limit, so at most
// 16384² texels per level (2 GiB as RGBA16F). The environment variable AHDPACK_MAX_SIZE (a whole
// number ≥ 1) overrides it for the whole process; set_max_image_size() overrides both (tests).
constexpr uint32_t kDefaultMaxImageSize = 16384;

// The limit in force: set_max_image_size's value, else AHDPACK_MAX_SIZE, else the default.
uint32_t max_image_size();

// Overrides the limit for this process; 0 returns to AHDPACK_MAX_SIZE / the default.
void set_max_image_size(uint32_t size);

// Throws ahd::Error("<path>: <w>x<h> is over the size limit of NxN texels per level
// (AHDPACK_MAX_SIZE raises it)") when w or h exceeds max_image_size(), and "<path>: empty image
// (WxH)" when either is 0.
void check_image_size(const std::string& path, uint64_t width, uint64_t height);

}  // namespace ahd
