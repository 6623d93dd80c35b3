// The few matrix operations src/scene and src/bakers/godot apply to an ImportedScene's node
// transforms (scene/assimp_module.h), computed exactly as Assimp's header-only aiMatrix4x4 /
// aiMatrix3x3 / aiVector3D / aiQuaternion do them (assimp/matrix4x4.inl, matrix3x3.inl,
// vector3.inl, quaternion.inl, Assimp 5.2): the same float operations in the same order, so the
// results — and the bytes of everything made from them — are those computed with Assimp's types
// before they moved behind the module. tests/unit/assimp_math_test.cpp compares them bit for bit.
#pragma once
#include <array>
#include <cmath>
#include <limits>

namespace ahd {

// A 4×4 matrix as aiMatrix4x4 holds it: rows a1 a2 a3 a4, b1 …, c1 …, d1 … (16 floats).
using Mat4f = std::array<float, 16>;
// A 3×3 matrix, rows a1 a2 a3, b1 …, c1 ….
using Mat3f = std::array<float, 9>;
struct Vec3f {
  float x = 0, y = 0, z = 0;
};

constexpr Mat4f kMat4fIdentity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

// aiMatrix4x4 a * b (operator*=: each element a sum over k in order).
inline Mat4f mat4_mul(const Mat4f& a, const Mat4f& b) {
  Mat4f r;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      r[size_t(i * 4 + j)] = b[size_t(j)] * a[size_t(i * 4)] + b[size_t(4 + j)] * a[size_t(i * 4 + 1)] +
                             b[size_t(8 + j)] * a[size_t(i * 4 + 2)] + b[size_t(12 + j)] * a[size_t(i * 4 + 3)];
  return r;
}

// aiMatrix4x4 * aiVector3D (a point: the translation added last).
inline Vec3f mat4_point(const Mat4f& m, const Vec3f& v) {
  return {m[0] * v.x + m[1] * v.y + m[2] * v.z + m[3], m[4] * v.x + m[5] * v.y + m[6] * v.z + m[7],
          m[8] * v.x + m[9] * v.y + m[10] * v.z + m[11]};
}

// aiMatrix3x3 * aiVector3D.
inline Vec3f mat3_mul(const Mat3f& m, const Vec3f& v) {
  return {m[0] * v.x + m[1] * v.y + m[2] * v.z, m[3] * v.x + m[4] * v.y + m[5] * v.z,
          m[6] * v.x + m[7] * v.y + m[8] * v.z};
}

// aiMatrix3x3(aiMatrix4x4): the upper-left 3×3.
inline Mat3f mat3_of(const Mat4f& m) { return {m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10]}; }

// aiMatrix3x3::Inverse() then Transpose() (NaN everywhere when singular, as Assimp).
inline Mat3f mat3_inverse_transpose(const Mat3f& m) {
  const float a1 = m[0], a2 = m[1], a3 = m[2], b1 = m[3], b2 = m[4], b3 = m[5], c1 = m[6], c2 = m[7], c3 = m[8];
  const float det = a1 * b2 * c3 - a1 * b3 * c2 + a2 * b3 * c1 - a2 * b1 * c3 + a3 * b1 * c2 - a3 * b2 * c1;
  if (det == 0.0f) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    return {nan, nan, nan, nan, nan, nan, nan, nan, nan};
  }
  const float invdet = 1.0f / det;
  const float r[9] = {invdet * (b2 * c3 - b3 * c2),  -invdet * (a2 * c3 - a3 * c2), invdet * (a2 * b3 - a3 * b2),
                      -invdet * (b1 * c3 - b3 * c1), invdet * (a1 * c3 - a3 * c1),  -invdet * (a1 * b3 - a3 * b1),
                      invdet * (b1 * c2 - b2 * c1),  -invdet * (a1 * c2 - a2 * c1), invdet * (a1 * b2 - a2 * b1)};
  return {r[0], r[3], r[6], r[1], r[4], r[7], r[2], r[5], r[8]};
}

// aiVector3D::Length().
inline float vec3_length(const Vec3f& v) { return std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z); }

// aiVector3D /= f (a multiplication by 1 / f; nothing when f is 0).
inline void vec3_div(Vec3f* v, float f) {
  if (f == 0.0f) return;
  const float inv = 1.0f / f;
  v->x *= inv, v->y *= inv, v->z *= inv;
}

// aiMatrix4x4::Determinant().
inline float mat4_determinant(const Mat4f& m) {
  const float a1 = m[0], a2 = m[1], a3 = m[2], a4 = m[3], b1 = m[4], b2 = m[5], b3 = m[6], b4 = m[7], c1 = m[8],
              c2 = m[9], c3 = m[10], c4 = m[11], d1 = m[12], d2 = m[13], d3 = m[14], d4 = m[15];
  return a1 * b2 * c3 * d4 - a1 * b2 * c4 * d3 + a1 * b3 * c4 * d2 - a1 * b3 * c2 * d4 + a1 * b4 * c2 * d3 -
         a1 * b4 * c3 * d2 - a2 * b3 * c4 * d1 + a2 * b3 * c1 * d4 - a2 * b4 * c1 * d3 + a2 * b4 * c3 * d1 -
         a2 * b1 * c3 * d4 + a2 * b1 * c4 * d3 + a3 * b4 * c1 * d2 - a3 * b4 * c2 * d1 + a3 * b1 * c2 * d4 -
         a3 * b1 * c4 * d2 + a3 * b2 * c4 * d1 - a3 * b2 * c1 * d4 - a4 * b1 * c2 * d3 + a4 * b1 * c3 * d2 -
         a4 * b2 * c3 * d1 + a4 * b2 * c1 * d3 - a4 * b3 * c1 * d2 + a4 * b3 * c2 * d1;
}

// aiMatrix4x4::Decompose(scaling, aiQuaternion rotation, position); quat = x, y, z, w.
inline void mat4_decompose(const Mat4f& m, Vec3f* scale, std::array<float, 4>* quat, Vec3f* position) {
  *position = {m[3], m[7], m[11]};
  Vec3f cols[3] = {{m[0], m[4], m[8]}, {m[1], m[5], m[9]}, {m[2], m[6], m[10]}};
  Vec3f s = {vec3_length(cols[0]), vec3_length(cols[1]), vec3_length(cols[2])};
  if (mat4_determinant(m) < 0) s = {-s.x, -s.y, -s.z};
  if (s.x) vec3_div(&cols[0], s.x);
  if (s.y) vec3_div(&cols[1], s.y);
  if (s.z) vec3_div(&cols[2], s.z);
  *scale = s;
  // aiQuaterniont(const aiMatrix3x3&) of the rotation whose columns are cols.
  const float a1 = cols[0].x, a2 = cols[1].x, a3 = cols[2].x, b1 = cols[0].y, b2 = cols[1].y, b3 = cols[2].y,
              c1 = cols[0].z, c2 = cols[1].z, c3 = cols[2].z;
  float x, y, z, w;
  const float t = a1 + b2 + c3;
  if (t > 0.0f) {
    const float q = std::sqrt(1 + t) * 2.0f;
    x = (c2 - b3) / q, y = (a3 - c1) / q, z = (b1 - a2) / q, w = 0.25f * q;
  } else if (a1 > b2 && a1 > c3) {
    const float q = std::sqrt(1.0f + a1 - b2 - c3) * 2.0f;
    x = 0.25f * q, y = (b1 + a2) / q, z = (a3 + c1) / q, w = (c2 - b3) / q;
  } else if (b2 > c3) {
    const float q = std::sqrt(1.0f + b2 - a1 - c3) * 2.0f;
    x = (b1 + a2) / q, y = 0.25f * q, z = (c2 + b3) / q, w = (a3 - c1) / q;
  } else {
    const float q = std::sqrt(1.0f + c3 - a1 - b2) * 2.0f;
    x = (a3 + c1) / q, y = (c2 + b3) / q, z = 0.25f * q, w = (b1 - a2) / q;
  }
  *quat = {x, y, z, w};
}

}  // namespace ahd
