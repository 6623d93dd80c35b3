// scene/assimp_math.h against Assimp's own header-only matrix types: every result bit for bit
// equal, so the node transforms, normals and Godot scale keys computed from an ImportedScene are
// those computed from aiScene before Assimp moved behind its module (same output bytes).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "scene/assimp_math.h"

#if __has_include(<assimp/types.h>)
#include <assimp/types.h>  // the math types and their inline operators (header-only: nothing linked)
#define AHD_HAVE_ASSIMP_HEADERS 1
#endif

namespace ahd {
namespace assimp_math_test {  // named: the unit tests are compiled in unity batches

#ifdef AHD_HAVE_ASSIMP_HEADERS

uint32_t bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}

aiMatrix4x4 to_ai(const Mat4f& m) {
  return aiMatrix4x4(m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8], m[9], m[10], m[11], m[12], m[13], m[14],
                     m[15]);
}

// Node transforms as files give them: a rotation (any of the quaternion's four branches), a scale
// (negative ones too: mirrored nodes), a translation; plus raw random matrices and singular ones.
std::vector<Mat4f> matrices() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1, 1);
  std::vector<Mat4f> out;
  for (int i = 0; i < 400; ++i) {
    aiQuaternion q(u(rng), u(rng), u(rng), u(rng));  // w, x, y, z
    q.Normalize();
    const aiMatrix3x3 r = q.GetMatrix();
    const float s[3] = {1 + 3 * u(rng), i % 3 == 0 ? -0.5f + u(rng) : 2 + u(rng), 0.01f + std::fabs(u(rng))};
    out.push_back({r.a1 * s[0], r.a2 * s[1], r.a3 * s[2], 10 * u(rng), r.b1 * s[0], r.b2 * s[1], r.b3 * s[2],
                   10 * u(rng), r.c1 * s[0], r.c2 * s[1], r.c3 * s[2], 10 * u(rng), 0, 0, 0, 1});
  }
  for (int i = 0; i < 100; ++i) {
    Mat4f m;
    for (float& f : m) f = u(rng) * 5;
    out.push_back(m);
  }
  out.push_back(kMat4fIdentity);
  out.push_back({-1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1});  // the quaternion's x/y branches
  out.push_back({-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1});
  out.push_back({1, 0, 0, 0, 0, -1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1});
  out.push_back({0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0, 3, 0, 0, 0, 1});  // singular: no inverse, zero scales
  return out;
}

TEST(AssimpMath, ProductsPointsAndNormalsMatchAssimpBitForBit) {
  const std::vector<Mat4f> ms = matrices();
  const aiVector3D v(0.3f, -1.7f, 2.5f);
  for (size_t i = 0; i + 1 < ms.size(); ++i) {
    const Mat4f p = mat4_mul(ms[i], ms[i + 1]);
    const aiMatrix4x4 ap = to_ai(ms[i]) * to_ai(ms[i + 1]);
    for (int k = 0; k < 16; ++k) ASSERT_EQ(bits(p[size_t(k)]), bits(ap[k / 4][k % 4])) << i << " " << k;
    const Vec3f q = mat4_point(p, {v.x, v.y, v.z});
    const aiVector3D aq = ap * v;
    EXPECT_EQ(bits(q.x), bits(aq.x));
    EXPECT_EQ(bits(q.y), bits(aq.y));
    EXPECT_EQ(bits(q.z), bits(aq.z));
    const Mat3f nm = mat3_inverse_transpose(mat3_of(p));
    aiMatrix3x3 anm(ap);
    anm.Inverse().Transpose();
    for (int k = 0; k < 9; ++k) ASSERT_EQ(bits(nm[size_t(k)]), bits(anm[k / 3][k % 3])) << i << " " << k;
    Vec3f n = mat3_mul(nm, {v.x, v.y, v.z});
    aiVector3D an = anm * v;
    const float len = vec3_length(n);
    ASSERT_EQ(bits(len), bits(an.Length()));
    if (len > 0 && std::isfinite(len)) vec3_div(&n, len), an /= an.Length();
    EXPECT_EQ(bits(n.x), bits(an.x));
    EXPECT_EQ(bits(n.y), bits(an.y));
    EXPECT_EQ(bits(n.z), bits(an.z));
  }
}

TEST(AssimpMath, DecomposeMatchesAssimpBitForBit) {
  int branches[4] = {0, 0, 0, 0};
  for (const Mat4f& m : matrices()) {
    Vec3f s, t;
    std::array<float, 4> q;
    mat4_decompose(m, &s, &q, &t);
    aiVector3D as, at;
    aiQuaternion aq;
    to_ai(m).Decompose(as, aq, at);
    const float ours[10] = {s.x, s.y, s.z, q[0], q[1], q[2], q[3], t.x, t.y, t.z};
    const float theirs[10] = {as.x, as.y, as.z, aq.x, aq.y, aq.z, aq.w, at.x, at.y, at.z};
    for (int k = 0; k < 10; ++k) ASSERT_EQ(bits(ours[k]), bits(theirs[k])) << k;
    // Which of the quaternion's branches ran: the component set to 0.25·s is the largest.
    int big = 0;
    for (int k = 1; k < 4; ++k)
      if (std::fabs(q[size_t(k)]) > std::fabs(q[size_t(big)])) big = k;
    ++branches[big];
  }
  for (int b = 0; b < 4; ++b) EXPECT_GT(branches[b], 0) << "quaternion branch " << b << " never ran";
}

#else

TEST(AssimpMath, MatchesAssimpBitForBit) { GTEST_SKIP() << "Assimp's headers are not installed here"; }

#endif

}  // namespace assimp_math_test
}  // namespace ahd
