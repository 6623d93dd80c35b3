#include "bakers/godot/godot_unwrap_key.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace ahd {

namespace {

// RFC 1321, section 3.4: per-round shift amounts; the sines' table is built as the RFC defines it.
// clang-format off
constexpr uint32_t kShift[64] = {7, 12, 17, 22, 7, 12, 17, 22, 7, 12, 17, 22, 7, 12, 17, 22,
                                 5, 9,  14, 20, 5, 9,  14, 20, 5, 9,  14, 20, 5, 9,  14, 20,
                                 4, 11, 16, 23, 4, 11, 16, 23, 4, 11, 16, 23, 4, 11, 16, 23,
                                 6, 10, 15, 21, 6, 10, 15, 21, 6, 10, 15, 21, 6, 10, 15, 21};
// clang-format on

struct Md5 {
  uint32_t s[4] = {0x67452301u, 0xefcdab89u, 0x98badcfeu, 0x10325476u};
  uint32_t k[64];
  uint8_t block[64];
  size_t used = 0;
  uint64_t bytes = 0;

  Md5() {
    for (int i = 0; i < 64; ++i) k[i] = uint32_t(std::floor(std::fabs(std::sin(double(i + 1))) * 4294967296.0));
  }
  static uint32_t rotl(uint32_t x, uint32_t c) { return (x << c) | (x >> (32 - c)); }
  void compress(const uint8_t* p) {
    uint32_t m[16];
    for (int i = 0; i < 16; ++i)
      m[i] = uint32_t(p[i * 4]) | uint32_t(p[i * 4 + 1]) << 8 | uint32_t(p[i * 4 + 2]) << 16 |
             uint32_t(p[i * 4 + 3]) << 24;
    uint32_t a = s[0], b = s[1], c = s[2], d = s[3];
    for (int i = 0; i < 64; ++i) {
      uint32_t f, g;
      if (i < 16) f = (b & c) | (~b & d), g = uint32_t(i);
      else if (i < 32) f = (d & b) | (~d & c), g = uint32_t(5 * i + 1) % 16;
      else if (i < 48) f = b ^ c ^ d, g = uint32_t(3 * i + 5) % 16;
      else f = c ^ (b | ~d), g = uint32_t(7 * i) % 16;
      const uint32_t t = d;
      d = c;
      c = b;
      b = b + rotl(a + f + k[i] + m[g], kShift[i]);
      a = t;
    }
    s[0] += a, s[1] += b, s[2] += c, s[3] += d;
  }
  void update(const void* data, size_t n) {
    const uint8_t* p = static_cast<const uint8_t*>(data);
    bytes += n;
    while (n > 0) {
      const size_t take = std::min(n, size_t(64) - used);
      std::memcpy(block + used, p, take);
      used += take, p += take, n -= take;
      if (used == 64) compress(block), used = 0;
    }
  }
  GodotUnwrapKey finish() {
    const uint64_t bits = bytes * 8;
    const uint8_t one = 0x80, zero = 0;
    update(&one, 1);
    while (used != 56) update(&zero, 1);
    uint8_t len[8];
    for (int i = 0; i < 8; ++i) len[i] = uint8_t(bits >> (8 * i));
    update(len, 8);
    GodotUnwrapKey out;
    for (int i = 0; i < 16; ++i) out[size_t(i)] = uint8_t(s[i / 4] >> (8 * (i % 4)));
    return out;
  }
};

// float arithmetic, one rounding per operation as Godot's real_t code does (x86-64: SSE, no FMA).
inline float fmul(float a, float b) { return a * b; }
inline float fadd(float a, float b) { return a + b; }

}  // namespace

GodotUnwrapKey md5_digest(const void* data, size_t size) {
  Md5 m;
  m.update(data, size);
  return m.finish();
}

void godot_node_scale(const float r[9], float scale[3]) {
  for (int c = 0; c < 3; ++c) {
    const float x2 = fmul(r[c], r[c]), y2 = fmul(r[3 + c], r[3 + c]), z2 = fmul(r[6 + c], r[6 + c]);
    scale[c] = std::sqrt(fadd(fadd(x2, y2), z2));
  }
}

void godot_basis_from_trs(const float q[4], const float sc[3], float r[9]) {
  // Basis(Quaternion) (core/math/basis.cpp set_quaternion), then · diag(scale).
  const float x = q[0], y = q[1], z = q[2], w = q[3];
  const float d = fadd(fadd(fadd(fmul(x, x), fmul(y, y)), fmul(z, z)), fmul(w, w));
  const float s = 2.0f / d;
  const float xs = x * s, ys = y * s, zs = z * s;
  const float wx = w * xs, wy = w * ys, wz = w * zs;
  const float xx = x * xs, xy = x * ys, xz = x * zs;
  const float yy = y * ys, yz = y * zs, zz = z * zs;
  const float rot[9] = {1.0f - (yy + zz), xy - wz,          xz + wy,  //
                        xy + wz,          1.0f - (xx + zz), yz - wx,  //
                        xz - wy,          yz + wx,          1.0f - (xx + yy)};
  const float diag[9] = {sc[0], 0, 0, 0, sc[1], 0, 0, 0, sc[2]};
  godot_basis_mul(rot, diag, r);
}

void godot_basis_mul(const float a[9], const float b[9], float out[9]) {
  float r[9];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      r[i * 3 + j] = fadd(fadd(fmul(a[i * 3], b[j]), fmul(a[i * 3 + 1], b[3 + j])), fmul(a[i * 3 + 2], b[6 + j]));
  std::memcpy(out, r, sizeof(r));
}

GodotUnwrapKey godot_unwrap_key(const std::vector<float>& positions, const std::vector<float>& normals,
                                const std::vector<uint32_t>& indices, const float scale[3], float texel_size) {
  const size_t n = positions.size() / 3;
  // The scale-only transform: Transform3D().scale(s): basis diag(s), origin 0 (adding the zero
  // origin turns a -0 coordinate into +0, which the key sees).
  std::vector<float> p(n * 3), nr(n * 3);
  for (size_t v = 0; v < n; ++v)
    for (int c = 0; c < 3; ++c) {
      const float* x = &positions[v * 3];
      // Basis::xform: row · v, the off-diagonal zeros included (they decide a zero's sign).
      const float row = fadd(fadd(fmul(c == 0 ? scale[0] : 0.0f, x[0]), fmul(c == 1 ? scale[1] : 0.0f, x[1])),
                             fmul(c == 2 ? scale[2] : 0.0f, x[2]));
      p[v * 3 + size_t(c)] = fadd(row, 0.0f);
    }
  // Normal basis: inverse().transposed() of diag(s) through Basis::inverse's cofactors.
  const float m[9] = {scale[0], 0, 0, 0, scale[1], 0, 0, 0, scale[2]};
  const float co[3] = {m[4] * m[8] - m[5] * m[7], m[5] * m[6] - m[3] * m[8], m[3] * m[7] - m[4] * m[6]};
  const float det = fadd(fadd(fmul(m[0], co[0]), fmul(m[1], co[1])), fmul(m[2], co[2]));
  const float s = 1.0f / det;
  const float inv[9] = {co[0] * s, (m[2] * m[7] - m[1] * m[8]) * s, (m[1] * m[5] - m[2] * m[4]) * s,
                        co[1] * s, (m[0] * m[8] - m[2] * m[6]) * s, (m[2] * m[3] - m[0] * m[5]) * s,
                        co[2] * s, (m[1] * m[6] - m[0] * m[7]) * s, (m[0] * m[4] - m[1] * m[3]) * s};
  const float nb[9] = {inv[0], inv[3], inv[6], inv[1], inv[4], inv[7], inv[2], inv[5], inv[8]};
  for (size_t v = 0; v < n && v * 3 + 2 < normals.size(); ++v) {
    const float* x = &normals[v * 3];
    float q[3];
    for (int c = 0; c < 3; ++c)
      q[c] = fadd(fadd(fmul(nb[c * 3], x[0]), fmul(nb[c * 3 + 1], x[1])), fmul(nb[c * 3 + 2], x[2]));
    const float l2 = fadd(fadd(fmul(q[0], q[0]), fmul(q[1], q[1])), fmul(q[2], q[2]));
    if (l2 == 0.0f) {
      nr[v * 3] = nr[v * 3 + 1] = nr[v * 3 + 2] = 0.0f;
      continue;
    }
    const float len = std::sqrt(l2);
    for (int c = 0; c < 3; ++c) nr[v * 3 + size_t(c)] = q[c] / len;
  }
  const float eps = 1.19209290e-7f;  // xatlas.h's epsilon, as importer_mesh.cpp uses it
  const auto d2 = [&](uint32_t a, uint32_t b) {
    const float dx = p[a * 3] - p[b * 3], dy = p[a * 3 + 1] - p[b * 3 + 1], dz = p[a * 3 + 2] - p[b * 3 + 2];
    return fadd(fadd(fmul(dx, dx), fmul(dy, dy)), fmul(dz, dz));
  };
  std::vector<int32_t> kept;
  kept.reserve(indices.size());
  for (size_t t = 0; t + 2 < indices.size(); t += 3) {
    const uint32_t a = indices[t], b = indices[t + 1], c = indices[t + 2];
    if (a >= n || b >= n || c >= n) continue;
    if (d2(a, b) < eps || d2(b, c) < eps || d2(c, a) < eps) continue;
    kept.insert(kept.end(), {int32_t(a), int32_t(b), int32_t(c)});
  }
  // Little-endian bytes, as Godot's editor platforms hold them in memory.
  Md5 h;
  h.update(&texel_size, sizeof(float));
  h.update(kept.data(), kept.size() * sizeof(int32_t));
  h.update(p.data(), p.size() * sizeof(float));
  h.update(nr.data(), nr.size() * sizeof(float));
  return h.finish();
}

std::string godot_unwrap_key_hex(const GodotUnwrapKey& key) {
  static const char* hex = "0123456789abcdef";
  std::string s;
  for (uint8_t b : key) s += hex[b >> 4], s += hex[b & 15];
  return s;
}

}  // namespace ahd
