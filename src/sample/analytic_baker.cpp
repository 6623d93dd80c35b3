#include "sample/analytic_baker.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "core/error.h"
#include "core/parallel.h"

namespace ahd {
namespace {

struct V3 {
  double x, y, z;
};
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator*(V3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

struct AreaLight {
  V3 centre, edge_u, edge_v, normal;  // emits on the side of `normal`
  V3 radiance;
};

struct Scene {
  V3 point_pos, point_intensity;
  AreaLight ceiling, bounce;
  V3 sky;
  V3 sphere_centre;
  double sphere_radius;
};

// A chart: plane origin and the world vectors spanned by atlas u (→ right) and v (→ down),
// and the tangent frame (rows: t, b, n) used for its SH.
struct Chart {
  V3 origin, du, dv;
  double frame[3][3];
};

// Deterministic [0,1) from a 32-bit engine, independent of the standard library's distributions.
double unit(std::mt19937& rng) { return double(rng() >> 8) * (1.0 / 16777216.0); }

Scene make_scene(uint32_t seed) {
  Scene s;
  s.point_pos = {0.45, 1.1, 1.15};
  s.point_intensity = {3.2, 2.9, 2.5};
  s.ceiling = {{-0.35, 1.8, 0.9}, {0.6, 0, 0}, {0, 0, 0.6}, {0, -1, 0}, {7.0, 7.0, 6.5}};
  s.bounce = {{0.99, 0.45, 0.9}, {0, 0.8, 0}, {0, 0, 0.8}, {-1, 0, 0}, {1.4, 0.38, 0.12}};
  s.sky = {0.05, 0.075, 0.12};
  s.sphere_centre = {0.12, 0.45, 0.75};
  s.sphere_radius = 0.22;
  if (seed != 0) {
    std::mt19937 rng(seed);
    auto jitter = [&](double a) { return (unit(rng) * 2.0 - 1.0) * a; };
    s.point_pos = s.point_pos + V3{jitter(0.4), jitter(0.3), jitter(0.4)};
    s.point_intensity = s.point_intensity * (0.5 + unit(rng));
    s.ceiling.centre = s.ceiling.centre + V3{jitter(0.4), 0, jitter(0.4)};
    s.bounce.radiance = {0.4 + unit(rng), 0.4 * unit(rng), 0.4 * unit(rng)};
    s.sphere_centre = s.sphere_centre + V3{jitter(0.2), jitter(0.1), jitter(0.2)};
  }
  return s;
}

// True when the segment p → q is blocked by the occluding sphere.
bool occluded(const Scene& s, V3 p, V3 q) {
  const V3 d = q - p;
  const V3 m = p - s.sphere_centre;
  const double a = dot(d, d), b = dot(m, d), c = dot(m, m) - s.sphere_radius * s.sphere_radius;
  const double disc = b * b - a * c;
  if (disc <= 0) return false;
  const double sq = std::sqrt(disc);
  const double t0 = (-b - sq) / a, t1 = (-b + sq) / a;
  return (t0 > 1e-9 && t0 < 1.0) || (t1 > 1e-9 && t1 < 1.0 && t0 < 0);
}

// Adds radiance `L` arriving from world direction w (unit) over solid angle `dw`.
void add_delta(const Chart& ch, V3 w, V3 L, double dw, int coeffs, float* sh) {
  const double lx = ch.frame[0][0] * w.x + ch.frame[0][1] * w.y + ch.frame[0][2] * w.z;
  const double ly = ch.frame[1][0] * w.x + ch.frame[1][1] * w.y + ch.frame[1][2] * w.z;
  const double lz = ch.frame[2][0] * w.x + ch.frame[2][1] * w.y + ch.frame[2][2] * w.z;
  double y[9];
  sh_basis(lx, ly, lz, coeffs, y);
  for (int k = 0; k < coeffs; ++k) {
    sh[k * 3 + 0] += float(L.x * dw * y[k]);
    sh[k * 3 + 1] += float(L.y * dw * y[k]);
    sh[k * 3 + 2] += float(L.z * dw * y[k]);
  }
}

void add_area_light(const Scene& s, const AreaLight& al, const Chart& ch, V3 p, int n, int coeffs, float* sh) {
  const double area = std::sqrt(dot(al.edge_u, al.edge_u)) * std::sqrt(dot(al.edge_v, al.edge_v));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const V3 q = al.centre + al.edge_u * ((i + 0.5) / n - 0.5) + al.edge_v * ((j + 0.5) / n - 0.5);
      const V3 to = q - p;
      const double r2 = dot(to, to);
      const V3 w = to * (1.0 / std::sqrt(r2));
      const double cos_light = -dot(w, al.normal);
      if (cos_light <= 0 || occluded(s, p, q)) continue;
      add_delta(ch, w, al.radiance, cos_light * area / (n * n) / r2, coeffs, sh);
    }
}

// Projection of the sky dome (world y > 0) onto the chart's local SH, by quadrature (no occlusion).
void sky_projection(const Scene& s, const Chart& ch, int coeffs, float* out) {
  std::fill(out, out + coeffs * 3, 0.0f);
  const int nt = 256, np = 512;
  std::vector<double> acc(size_t(coeffs) * 3, 0.0);
  for (int it = 0; it < nt; ++it) {
    const double ct = 1.0 - 2.0 * (it + 0.5) / nt;  // uniform in cos θ
    const double st = std::sqrt(1.0 - ct * ct);
    for (int ip = 0; ip < np; ++ip) {
      const double ph = 2.0 * kPi * (ip + 0.5) / np;
      const V3 w{st * std::cos(ph), ct, st * std::sin(ph)};
      // Sky above the horizon, and only what reaches the front of the surface.
      if (w.y <= 0 || dot(w, V3{ch.frame[2][0], ch.frame[2][1], ch.frame[2][2]}) <= 0) continue;
      float tmp[27] = {};
      add_delta(ch, w, s.sky, 4.0 * kPi / (nt * np), coeffs, tmp);
      for (int k = 0; k < coeffs * 3; ++k) acc[k] += tmp[k];
    }
  }
  for (int k = 0; k < coeffs * 3; ++k) out[k] = float(acc[k]);
}

}  // namespace

ShImage bake_analytic_scene(const BakerOptions& opt) {
  if (opt.width < 1 || opt.height < 1 || opt.width > 65536 || opt.height > 65536)
    throw Error("analytic baker: size must be between 1 and 65536");
  ShImage img = make_sh_image(opt.width, opt.height, opt.coeffs);
  Scene scene = make_scene(opt.seed);
  scene.point_intensity = scene.point_intensity * opt.point_scale;
  scene.sky = scene.sky * opt.sky_scale;
  scene.ceiling.radiance = scene.ceiling.radiance * opt.ceiling_scale;
  scene.bounce.radiance = scene.bounce.radiance * opt.bounce_scale;

  const Chart floor{{-1, 0, 0}, {2, 0, 0}, {0, 0, 2}, {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}}};
  const Chart wall{{-1, 2, 0}, {2, 0, 0}, {0, -2, 0}, {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  float sky[2][27];
  sky_projection(scene, floor, opt.coeffs, sky[0]);
  sky_projection(scene, wall, opt.coeffs, sky[1]);

  // Atlas: floor chart on the left half, wall chart on the right, `gutter` empty texels around
  // each (none for tiny maps, where every texel is covered).
  const int w = opt.width, h = opt.height;
  const int gutter = std::min(w, h) >= 16 ? std::max(1, std::min(w, h) / 64) : 0;
  const int half = w >= 2 ? w / 2 : w;
  parallel_for(size_t(h), opt.threads, 1, [&](size_t yy) {
    const int y = int(yy);
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const bool on_wall = x >= half;
      const int x0 = on_wall ? half : 0, x1 = on_wall ? w : half;
      const bool inside = x >= x0 + gutter && x < x1 - gutter && y >= gutter && y < h - gutter;
      img.coverage[i] = inside ? 1 : 0;
      if (!inside) continue;
      const Chart& ch = on_wall ? wall : floor;
      const double u = (x - x0 - gutter + 0.5) / double(x1 - x0 - 2 * gutter);
      const double v = (y - gutter + 0.5) / double(h - 2 * gutter);
      const V3 p = ch.origin + ch.du * u + ch.dv * v;
      float* sh = img.texel(i);
      std::copy(sky[on_wall], sky[on_wall] + opt.coeffs * 3, sh);
      // Point light: a delta of intensity I/r² from its direction (hard shadow).
      const V3 to = scene.point_pos - p;
      const double r2 = dot(to, to);
      if (opt.point_scale != 0.0 && !occluded(scene, p, scene.point_pos))
        add_delta(ch, to * (1.0 / std::sqrt(r2)), scene.point_intensity, 1.0 / r2, opt.coeffs, sh);
      if (opt.ceiling_scale != 0.0) add_area_light(scene, scene.ceiling, ch, p, opt.area_samples, opt.coeffs, sh);
      if (opt.bounce_scale != 0.0)
        add_area_light(scene, scene.bounce, ch, p, std::max(2, opt.area_samples * 3 / 4), opt.coeffs, sh);
    }
  });
  return img;
}

}  // namespace ahd
