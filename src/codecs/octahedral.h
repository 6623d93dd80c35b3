// Octahedral direction encodings (unit vector ↔ 2 numbers in [-1,1]).
//   hemi-octahedral: the upper hemisphere (z ≥ 0) onto the full square — twice the precision of
//     the full octahedral map for tangent-space directions, which is where AHD's d lives.
//   octahedral: the whole sphere (for world-space directions).
#pragma once

namespace ahd {

// Requires d[2] ≥ 0 (a lower-hemisphere d is mirrored to z ≥ 0). Writes uv in [-1,1]².
void hemi_oct_encode(const double d[3], double uv[2]);
// Any uv in [-1,1]² → unit d with d[2] ≥ 0.
void hemi_oct_decode(const double uv[2], double d[3]);

// A stored direction → hemi-octahedral uv in [0,1]² (what the UNORM direction planes hold; a
// d[2] < 0 or NaN is taken as 0). Inline: the planes' per-texel loops call it.
inline void hemi_oct_unit_uv(const float d[3], float uv01[2]) {
  const double dd[3] = {d[0], d[1], d[2] > 0.0f ? double(d[2]) : 0.0};
  double uv[2];
  hemi_oct_encode(dd, uv);
  uv01[0] = float(uv[0] * 0.5 + 0.5);
  uv01[1] = float(uv[1] * 0.5 + 0.5);
}

void oct_encode(const double d[3], double uv[2]);
void oct_decode(const double uv[2], double d[3]);

// UNORM8 helpers: [-1,1] ↔ byte with 0 ↔ 127.5 (round to nearest).
unsigned char snorm_to_unorm8(double v);
double unorm8_to_snorm(unsigned char b);

}  // namespace ahd
