// A conversion's coded planes back to what the reference decoder reads: I_z, the unit direction and
// the ratio per texel — for a whole level, or for single texels (the error estimate decodes only
// the blocks of its sampled texels).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/pixel_format.h"
#include "core/texture.h"
#include "fit/hemisphere_error.h"

namespace ahd {

struct Plane {
  std::string name;  // "iz", "dir", "ratio", "dirratio" or "coverage"
  Texture texture;
};

// One mip level of a conversion's planes: I_z always; dir + ratio, or the packed dirratio, or
// neither (a plain lightmap: d = z, ratio = 1). The pointers must outlive the view.
struct CodedLevel {
  PixelFormat iz_format{}, dir_format{}, ratio_format{}, dirratio_format{};
  const TextureLevel* iz = nullptr;
  const TextureLevel* dir = nullptr;
  const TextureLevel* ratio = nullptr;
  const TextureLevel* dirratio = nullptr;
};

// The decoded value of every texel of one level's planes (as the reference decoder reads them):
// iz (3 floats), d (unit, 3 floats), ratio (3 floats).
struct DecodedPlanes {
  int width = 0, height = 0;
  std::vector<float> iz, d, ratio;
};

// Decodes the planes of a conversion at mip level `level`. Safe on untrusted planes: formats,
// level counts and sizes are validated before any texel is decoded; throws ahd::Error.
DecodedPlanes decode_planes(const std::vector<Plane>& planes, bool ratio_rgb, int level = 0);

// Decodes a whole level of planes this build wrote (sizes not re-validated: not for untrusted input).
DecodedPlanes decode_level(const CodedLevel& level, bool ratio_rgb);

// Texel (x, y) of a level as decode_level gives it, decoding only the blocks that hold it.
void decode_texel(const CodedLevel& level, bool ratio_rgb, uint32_t x, uint32_t y, float iz[3], float d[3],
                  float ratio[3]);

// Hemi-octahedral uv in [0,1]² (what UNORM direction planes store) → unit direction.
void unit_uv_to_dir(const float uv01[2], float d[3]);

// The AHD lobes the decoded planes describe (for measure_error).
std::vector<AhdLobe> lobes_from_planes(const DecodedPlanes& p, double dz_min);

}  // namespace ahd
