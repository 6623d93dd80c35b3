// Spherical-harmonics math of the tool's one canonical form (docs/conventions.md "Canonical SH and conventions"):
// real SH, order 0..8 = Y00, y, z, x, xy, yz, 3z²-1, xz, x²-y² (no Condon-Shortley sign),
// coefficients = projection of incident RADIANCE, in the texel's local frame (z = surface normal).
// Irradiance means E(n) = ∫ L(ω) max(0, n·ω) dω (no 1/π).
#pragma once

namespace ahd {

constexpr int kShCoeffsL0 = 1;  // a plain lightmap: irradiance only, no direction (L1 = L2 = 0)
constexpr int kShCoeffsL1 = 4;
constexpr int kShCoeffsL2 = 9;

// Basis constants of the canonical order.
constexpr double kY00 = 0.28209479177387814;   // 1/(2√π)
constexpr double kY1 = 0.4886025119029199;     // √3/(2√π)
constexpr double kY2a = 1.0925484305920792;    // √15/(2√π)   (xy, yz, xz)
constexpr double kY20 = 0.31539156525252005;   // √5/(4√π)    (3z²-1)
constexpr double kY22 = 0.5462742152960396;    // √15/(4√π)   (x²-y²)

// Clamped-cosine convolution weights per band (Ramamoorthi–Hanrahan): Â0 = π, Â1 = 2π/3, Â2 = π/4.
constexpr double kPi = 3.14159265358979323846;
constexpr double kA0 = kPi;
constexpr double kA1 = 2.0 * kPi / 3.0;
constexpr double kA2 = kPi / 4.0;

// True for the coefficient counts an SH image can hold: 1 (L0), 4 (L1) or 9 (L2).
constexpr bool valid_sh_coeffs(int count) {
  return count == kShCoeffsL0 || count == kShCoeffsL1 || count == kShCoeffsL2;
}

// "L0", "L1" or "L2" for a valid count.
constexpr const char* sh_order_name(int count) {
  return count == kShCoeffsL2 ? "L2" : count == kShCoeffsL1 ? "L1" : "L0";
}

// Evaluates the first `count` (4 or 9) basis functions at the unit direction (x, y, z).
void sh_basis(double x, double y, double z, int count, double* out);

// Irradiance of one colour channel as a polynomial in the unit normal n:
//   E(n) = e0 + e·n + nᵀ Q n          (Q symmetric; zero for L1 input)
// The irradiance of band-limited (L1/L2) radiance is exactly such a polynomial, which makes rotation
// (a change of frame) and the hemisphere integrals of the fit closed-form.
struct IrradiancePoly {
  double e0 = 0;
  double e[3] = {0, 0, 0};
  double q[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
};

// Whether any of the three channels has an L2 band: a q entry other than ±0 (L1 texels have none,
// whatever their frame). Code that skips the L2 terms for the others asks this.
inline bool has_l2(const IrradiancePoly p[3]) {
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (p[c].q[i][j] != 0.0) return true;
  return false;
}

// The constant part of the irradiance from the L0 coefficient c0: IrradiancePoly::e0 of an L0 or
// L1 texel (an L0 texel's irradiance for every normal).
inline double l0_irradiance(double c0) { return kA0 * kY00 * c0; }

// Converts `count` (4 or 9) radiance-SH coefficients of one channel, read at stride `stride`
// (coeff k at sh[k * stride]), into the irradiance polynomial.
// Inline: every stage asks for a texel's polynomials (local_polys), millions of times a map.
inline IrradiancePoly irradiance_poly(const float* sh, int count, int stride) {
  IrradiancePoly p;
  auto c = [&](int k) { return double(sh[k * stride]); };
  p.e0 = l0_irradiance(c(0));
  if (count >= 4) {  // L0 images (plain lightmaps) have no L1: e stays 0
    p.e[0] = kA1 * kY1 * c(3);
    p.e[1] = kA1 * kY1 * c(1);
    p.e[2] = kA1 * kY1 * c(2);
  }
  if (count >= 9) {
    // Band 2 times Â2; the constant part of Y20 (−1) goes into e0.
    const double k = kA2;
    p.e0 -= k * kY20 * c(6);
    p.q[0][1] = p.q[1][0] = 0.5 * k * kY2a * c(4);
    p.q[1][2] = p.q[2][1] = 0.5 * k * kY2a * c(5);
    p.q[0][2] = p.q[2][0] = 0.5 * k * kY2a * c(7);
    p.q[2][2] = 3.0 * k * kY20 * c(6);
    p.q[0][0] = k * kY22 * c(8);
    p.q[1][1] = -k * kY22 * c(8);
  }
  return p;
}

// E(n) for a unit normal n.
double eval_irradiance(const IrradiancePoly& p, const double n[3]);

// The same polynomial expressed in another frame: returns p' with p'(n') = p(Rᵀ n'), where the
// rows of R are the new frame's x, y, z axes given in the old frame (n' = R n).
IrradiancePoly rotate_poly(const IrradiancePoly& p, const double R[3][3]);

// Right-handed orthonormal frame around a unit normal n (Duff et al. 2017, "Building an
// Orthonormal Basis, Revisited"): rows of R are (tangent, bitangent, n). The branch follows
// n.z >= 0 (z = ±0.0 both take the + branch), so the frame jumps where n.z changes sign (a chart
// straddling z = 0 holds two frames; docs/godot.md). This is THE frame ahdpack uses for
// world-space SH; the shader snippets build the same one, bit for bit in the branch.
void frame_from_normal(const double n[3], double R[3][3]);

}  // namespace ahd
