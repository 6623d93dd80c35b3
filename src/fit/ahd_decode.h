// The reference decoder: THE definition of how ahdpack's planes are read. The GLSL/HLSL snippets
// in formats/shaders/ implement exactly this.
#pragma once
#include <cmath>

namespace ahd {

// The horizon rule, shared by the encoder and every decoder: a unit d with d_z < dz_min is tilted
// up to d_z = dz_min keeping its azimuth (straight down, which has none, becomes z). Returns true
// when it tilted. Because decoders apply it too, d_z ≥ dz_min holds after quantisation and
// filtering, so C_d = (I_z − C_a)/d_z ≤ I_z/dz_min and I(z) = I_z exactly.
// Inline: the direction search applies it to every direction it tries.
inline bool tilt_above_horizon(double d[3], double dz_min) {
  if (d[2] >= dz_min) return false;
  const double rxy = std::sqrt(d[0] * d[0] + d[1] * d[1]);
  if (rxy > 1e-12) {
    const double sxy = std::sqrt(1.0 - dz_min * dz_min);
    d[0] *= sxy / rxy, d[1] *= sxy / rxy, d[2] = dz_min;
  } else {
    d[0] = 0, d[1] = 0, d[2] = 1;
  }
  return true;
}

// From (possibly filtered) plane values to the AHD colours:
//   d ← normalise(d), then the horizon rule;  C_a = ratio · I_z,   C_d = (I_z − C_a) / d_z
// `d` need not be unit length; ratio is per channel (luminance form: all
// three equal). Outputs are ≥ 0 whenever iz ≥ 0 and ratio ∈ [0,1].
void decode_colours(const float iz[3], const float d[3], const float ratio[3], double dz_min,
                    double ca[3], double cd[3], double unit_d[3]);

// Irradiance for the tangent-space unit normal n:  I(n) = C_a + max(0, n·d) C_d.
void decode_irradiance(const float iz[3], const float d[3], const float ratio[3], const double n[3],
                       double dz_min, double out[3]);

}  // namespace ahd
