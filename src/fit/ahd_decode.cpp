#include "fit/ahd_decode.h"

#include <algorithm>
#include <cmath>

namespace ahd {

void decode_colours(const float iz[3], const float d[3], const float ratio[3], double dz_min,
                    double ca[3], double cd[3], double unit_d[3]) {
  const double len = std::sqrt(double(d[0]) * d[0] + double(d[1]) * d[1] + double(d[2]) * d[2]);
  if (len > 0) {
    for (int i = 0; i < 3; ++i) unit_d[i] = d[i] / len;
  } else {
    unit_d[0] = 0, unit_d[1] = 0, unit_d[2] = 1;
  }
  tilt_above_horizon(unit_d, dz_min);
  const double dz = unit_d[2];
  for (int c = 0; c < 3; ++c) {
    ca[c] = double(ratio[c]) * iz[c];
    cd[c] = (double(iz[c]) - ca[c]) / dz;
  }
}

void decode_irradiance(const float iz[3], const float d[3], const float ratio[3], const double n[3],
                       double dz_min, double out[3]) {
  double ca[3], cd[3], u[3];
  decode_colours(iz, d, ratio, dz_min, ca, cd, u);
  const double cosine = std::max(0.0, n[0] * u[0] + n[1] * u[1] + n[2] * u[2]);
  for (int c = 0; c < 3; ++c) out[c] = ca[c] + cosine * cd[c];
}

}  // namespace ahd
