#include "codecs/octahedral.h"

#include <algorithm>
#include <cmath>

namespace ahd {

void hemi_oct_encode(const double d[3], double uv[2]) {
  const double l1 = std::fabs(d[0]) + std::fabs(d[1]) + std::fabs(d[2]);
  const double px = l1 > 0 ? d[0] / l1 : 0.0, py = l1 > 0 ? d[1] / l1 : 0.0;
  // Rotate the diamond |px|+|py| ≤ 1 by 45° onto the square.
  uv[0] = px + py;
  uv[1] = px - py;
}

void hemi_oct_decode(const double uv[2], double d[3]) {
  const double px = 0.5 * (uv[0] + uv[1]), py = 0.5 * (uv[0] - uv[1]);
  const double pz = std::max(0.0, 1.0 - std::fabs(px) - std::fabs(py));
  const double len = std::sqrt(px * px + py * py + pz * pz);
  d[0] = px / len, d[1] = py / len, d[2] = pz / len;
}

void oct_encode(const double d[3], double uv[2]) {
  const double l1 = std::fabs(d[0]) + std::fabs(d[1]) + std::fabs(d[2]);
  double px = l1 > 0 ? d[0] / l1 : 0.0, py = l1 > 0 ? d[1] / l1 : 0.0;
  if (d[2] < 0) {
    const double ox = px, oy = py;
    px = (1.0 - std::fabs(oy)) * (ox >= 0 ? 1.0 : -1.0);
    py = (1.0 - std::fabs(ox)) * (oy >= 0 ? 1.0 : -1.0);
  }
  uv[0] = px, uv[1] = py;
}

void oct_decode(const double uv[2], double d[3]) {
  double px = uv[0], py = uv[1];
  const double pz = 1.0 - std::fabs(px) - std::fabs(py);
  if (pz < 0) {
    const double ox = px, oy = py;
    px = (1.0 - std::fabs(oy)) * (ox >= 0 ? 1.0 : -1.0);
    py = (1.0 - std::fabs(ox)) * (oy >= 0 ? 1.0 : -1.0);
  }
  const double len = std::sqrt(px * px + py * py + pz * pz);
  d[0] = px / len, d[1] = py / len, d[2] = pz / len;
}

unsigned char snorm_to_unorm8(double v) {
  const double x = std::clamp((v * 0.5 + 0.5) * 255.0, 0.0, 255.0);
  return static_cast<unsigned char>(std::lround(x));
}

double unorm8_to_snorm(unsigned char b) { return b / 255.0 * 2.0 - 1.0; }

}  // namespace ahd
