#include "sh/sh.h"

#include <cmath>

namespace ahd {

void sh_basis(double x, double y, double z, int count, double* out) {
  out[0] = kY00;
  out[1] = kY1 * y;
  out[2] = kY1 * z;
  out[3] = kY1 * x;
  if (count <= 4) return;
  out[4] = kY2a * x * y;
  out[5] = kY2a * y * z;
  out[6] = kY20 * (3.0 * z * z - 1.0);
  out[7] = kY2a * x * z;
  out[8] = kY22 * (x * x - y * y);
}

double eval_irradiance(const IrradiancePoly& p, const double n[3]) {
  double v = p.e0 + p.e[0] * n[0] + p.e[1] * n[1] + p.e[2] * n[2];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) v += n[i] * p.q[i][j] * n[j];
  return v;
}

IrradiancePoly rotate_poly(const IrradiancePoly& p, const double R[3][3]) {
  // p(n) with n = Rᵀ n':  e·n = (R e)·n',  nᵀQn = n'ᵀ (R Q Rᵀ) n'.
  IrradiancePoly r;
  r.e0 = p.e0;
  for (int i = 0; i < 3; ++i) {
    r.e[i] = R[i][0] * p.e[0] + R[i][1] * p.e[1] + R[i][2] * p.e[2];
  }
  double qr[3][3];  // Q Rᵀ
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) qr[i][j] = p.q[i][0] * R[j][0] + p.q[i][1] * R[j][1] + p.q[i][2] * R[j][2];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.q[i][j] = R[i][0] * qr[0][j] + R[i][1] * qr[1][j] + R[i][2] * qr[2][j];
  return r;
}

void frame_from_normal(const double n[3], double R[3][3]) {
  // `>= 0`, not copysign: z = −0.0 (a wall facing ±x in a Y-up engine) takes the + branch, as the
  // shader snippets' `ng.z >= 0.0` does — a GPU cannot be relied on to keep the sign of a zero.
  const double sign = n[2] >= 0.0 ? 1.0 : -1.0;
  const double a = -1.0 / (sign + n[2]);
  const double b = n[0] * n[1] * a;
  R[0][0] = 1.0 + sign * n[0] * n[0] * a;
  R[0][1] = sign * b;
  R[0][2] = -sign * n[0];
  R[1][0] = b;
  R[1][1] = sign + n[1] * n[1] * a;
  R[1][2] = -n[1];
  R[2][0] = n[0];
  R[2][1] = n[1];
  R[2][2] = n[2];
}

}  // namespace ahd
