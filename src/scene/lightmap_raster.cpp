#include "scene/lightmap_raster.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "core/error.h"

namespace ahd {

namespace {

struct Pt {
  double x, y;
};

// A convex polygon. Each half-plane clip of a convex polygon adds at most one vertex: the
// triangle (3) clipped by the image (4 planes), a column (2) and a row (2) stays ≤ 11. The
// capacity leaves room for rounding making a sliver very slightly non-convex; beyond it
// vertices are dropped rather than written out of bounds.
struct Poly {
  std::array<Pt, 32> p;
  int n = 0;
  void push(const Pt& q) {
    if (n < int(p.size())) p[size_t(n++)] = q;
  }
};

double coord(const Pt& p, int axis) { return axis == 0 ? p.x : p.y; }

// The point where segment a→b crosses the line `axis = c` (a and b on opposite sides). The other
// coordinate is interpolated from the endpoint nearer the line, so a vertex at 1e30 does not wipe
// out the precision of a crossing inside the image; the clipped coordinate is set to c exactly,
// so an edge lying on a texel boundary gives exactly zero area beyond it.
Pt crossing(const Pt& a, const Pt& b, int axis, double c) {
  const double da = coord(a, axis) - c, db = coord(b, axis) - c;
  const double oa = coord(a, 1 - axis), ob = coord(b, 1 - axis);
  const double t = da / (da - db);  // from a
  const double o = t <= 0.5 ? oa + t * (ob - oa) : ob + (db / (db - da)) * (oa - ob);
  return axis == 0 ? Pt{c, o} : Pt{o, c};
}

// Sutherland–Hodgman against one axis-aligned half-plane: keeps coord ≥ c (keep_ge) or ≤ c.
Poly clip(const Poly& in, int axis, double c, bool keep_ge) {
  Poly out;
  for (int i = 0; i < in.n; ++i) {
    const Pt& a = in.p[size_t(i)];
    const Pt& b = in.p[size_t((i + 1) % in.n)];
    const bool ia = keep_ge ? coord(a, axis) >= c : coord(a, axis) <= c;
    const bool ib = keep_ge ? coord(b, axis) >= c : coord(b, axis) <= c;
    if (ia) out.push(a);
    if (ia != ib) out.push(crossing(a, b, axis, c));
  }
  return out;
}

// The texel columns (axis 0) or rows (axis 1) a polygon's extent along `axis` touches, within 0..size−1.
void cell_span(const Poly& q, int axis, int size, int* first, int* last) {
  double lo = coord(q.p[0], axis), hi = lo;
  for (int i = 1; i < q.n; ++i) lo = std::min(lo, coord(q.p[size_t(i)], axis)), hi = std::max(hi, coord(q.p[size_t(i)], axis));
  *first = std::max(0, int(std::floor(lo)));
  *last = std::min(size - 1, int(std::ceil(hi)) - 1);
}

// Signed area and centroid by a fan from vertex 0 (differences first: exact zero for vertices on
// a common line, precise for polygons far from the origin).
double area_centroid(const Poly& q, Pt* centroid) {
  double a2 = 0, cx = 0, cy = 0;
  const Pt o = q.p[0];
  for (int i = 1; i + 1 < q.n; ++i) {
    const double x1 = q.p[size_t(i)].x - o.x, y1 = q.p[size_t(i)].y - o.y;
    const double x2 = q.p[size_t(i + 1)].x - o.x, y2 = q.p[size_t(i + 1)].y - o.y;
    const double w = x1 * y2 - x2 * y1;
    a2 += w;
    cx += w * (x1 + x2);
    cy += w * (y1 + y2);
  }
  if (std::fabs(a2) > 1e-12) {
    *centroid = {o.x + cx / (3 * a2), o.y + cy / (3 * a2)};
  } else {  // a sliver: the weighted formula cancels out; the vertex mean is inside it anyway
    double sx = 0, sy = 0;
    for (int i = 0; i < q.n; ++i) sx += q.p[size_t(i)].x, sy += q.p[size_t(i)].y;
    *centroid = {sx / q.n, sy / q.n};
  }
  return 0.5 * a2;
}

using V3 = std::array<double, 3>;

double length(const V3& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

// Unit vector, or false when v is zero or not finite.
bool normalise(V3& v) {
  const double l = length(v);
  if (!(l > 1e-30) || !std::isfinite(l)) return false;
  for (double& c : v) c /= l;
  return true;
}

}  // namespace

RasterisedNormals rasterise_lightmap_normals(const MeshTriangles& mesh, int width, int height) {
  if (width < 1 || height < 1 || width > 65536 || height > 65536)
    throw Error("lightmap rasteriser: size " + std::to_string(width) + "x" + std::to_string(height) +
                " outside 1..65536");
  const size_t verts = mesh.positions.size() / 3;
  if (mesh.positions.size() % 3 != 0 || mesh.uv.size() != verts * 2 ||
      !(mesh.normals.empty() || mesh.normals.size() == mesh.positions.size()) || mesh.indices.size() % 3 != 0)
    throw Error("lightmap rasteriser: inconsistent mesh buffers (positions " + std::to_string(mesh.positions.size()) +
                ", normals " + std::to_string(mesh.normals.size()) + ", uv " + std::to_string(mesh.uv.size()) +
                ", indices " + std::to_string(mesh.indices.size()) + ")");
  for (uint32_t i : mesh.indices)
    if (i >= verts)
      throw Error("lightmap rasteriser: index " + std::to_string(i) + " out of range (" + std::to_string(verts) +
                  " vertices)");

  RasterisedNormals out;
  out.width = width;
  out.height = height;
  const size_t texels = size_t(width) * height;
  out.normals.assign(texels * 3, 0.0f);
  out.coverage.assign(texels, 0);
  out.triangle.assign(texels, -1);
  std::vector<double> best(texels, 0.0);  // the winner's overlap area (texel = 1)
  // A texel a triangle covers whole cannot be taken from it (no overlap exceeds the texel; ties keep
  // the lower index), so it is closed: per column, next_open[x·(H+1) + y] leads (union-find, path
  // halving) to the first open texel at or below y, and each triangle visits only open texels. Without
  // it, N triangles spanning the map cost N·W·H clips (200k triangles at 256² did not finish in
  // 120 s); with it, a triangle costs its columns plus the texels it does not close.
  const size_t col_stride = size_t(height) + 1;
  std::vector<int32_t> next_open(size_t(width) * col_stride);
  for (size_t x = 0; x < size_t(width); ++x)
    for (size_t y = 0; y < col_stride; ++y) next_open[x * col_stride + y] = int32_t(y);
  auto find_open = [&](int x, int y) {
    int32_t* col = &next_open[size_t(x) * col_stride];
    while (col[y] != y) {
      col[y] = col[col[y]];
      y = col[y];
    }
    return y;
  };
  // Rounding in the clipped cell's area is far below this; a cell covered whole has area 1.
  constexpr double kWhole = 1.0 - 1e-9;

  const double W = width, H = height;
  const size_t tris = mesh.indices.size() / 3;
  for (size_t t = 0; t < tris; ++t) {
    const uint32_t* idx = &mesh.indices[t * 3];
    // Pixel space: x = u·W, y = (1 − v)·H (row 0 at the top).
    Pt P[3];
    V3 pos[3];
    bool finite = true;
    for (int k = 0; k < 3; ++k) {
      const float* uv = &mesh.uv[size_t(idx[k]) * 2];
      const float* p = &mesh.positions[size_t(idx[k]) * 3];
      P[k] = {double(uv[0]) * W, (1.0 - double(uv[1])) * H};
      pos[k] = {p[0], p[1], p[2]};
      finite = finite && std::isfinite(P[k].x) && std::isfinite(P[k].y) && std::isfinite(pos[k][0]) &&
               std::isfinite(pos[k][1]) && std::isfinite(pos[k][2]);
    }
    if (!finite) continue;
    const double d2 = (P[1].x - P[0].x) * (P[2].y - P[0].y) - (P[2].x - P[0].x) * (P[1].y - P[0].y);
    if (d2 == 0 || !std::isfinite(d2)) continue;  // no UV area: it covers nothing
    const double orient = d2 > 0 ? 1.0 : -1.0;

    const V3 e1 = {pos[1][0] - pos[0][0], pos[1][1] - pos[0][1], pos[1][2] - pos[0][2]};
    const V3 e2 = {pos[2][0] - pos[0][0], pos[2][1] - pos[0][1], pos[2][2] - pos[0][2]};
    V3 face = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    const bool has_face = normalise(face);
    V3 vn[3];
    bool has_vertex = !mesh.normals.empty();
    for (int k = 0; k < 3 && has_vertex; ++k) {
      const float* n = &mesh.normals[size_t(idx[k]) * 3];
      vn[k] = {n[0], n[1], n[2]};
      has_vertex = normalise(vn[k]);
    }
    if (!has_vertex && !has_face) continue;  // no normal to give

    Poly tri;
    for (const Pt& p : P) tri.push(p);
    Poly q = clip(clip(clip(clip(tri, 0, 0.0, true), 0, W, false), 1, 0.0, true), 1, H, false);
    if (q.n < 3) continue;
    int cx0, cx1;
    cell_span(q, 0, width, &cx0, &cx1);
    int qy0, qy1;
    cell_span(q, 1, height, &qy0, &qy1);
    for (int x = cx0; x <= cx1; ++x) {
      if (find_open(x, qy0) > qy1) continue;  // every texel the triangle could reach here is closed
      const Poly col = clip(clip(q, 0, double(x), true), 0, double(x + 1), false);
      if (col.n < 3) continue;
      int cy0, cy1;
      cell_span(col, 1, height, &cy0, &cy1);
      for (int y = find_open(x, cy0); y <= cy1; y = find_open(x, y + 1)) {
        const Poly cell = clip(clip(col, 1, double(y), true), 1, double(y + 1), false);
        if (cell.n < 3) continue;
        Pt c;
        const double a = orient * area_centroid(cell, &c);
        const size_t i = size_t(y) * width + x;
        if (!(a > best[i])) continue;  // strict: on a tie the lower triangle index stays
        best[i] = a;
        if (a >= kWhole) next_open[size_t(x) * col_stride + size_t(y)] = int32_t(y + 1);  // closed
        out.coverage[i] = 1;
        out.triangle[i] = int32_t(t);
        V3 n = face;
        if (has_vertex) {
          // Barycentric weights of the centroid; clamped because rounding may put a sliver's
          // centroid a hair outside the triangle.
          double l1 = ((c.x - P[0].x) * (P[2].y - P[0].y) - (P[2].x - P[0].x) * (c.y - P[0].y)) / d2;
          double l2 = ((P[1].x - P[0].x) * (c.y - P[0].y) - (c.x - P[0].x) * (P[1].y - P[0].y)) / d2;
          l1 = std::clamp(l1, 0.0, 1.0);
          l2 = std::clamp(l2, 0.0, 1.0);
          const double s = l1 + l2;
          if (s > 1) l1 /= s, l2 /= s;
          const double l0 = 1 - l1 - l2;
          V3 m;
          for (int k = 0; k < 3; ++k) m[size_t(k)] = l0 * vn[0][size_t(k)] + l1 * vn[1][size_t(k)] + l2 * vn[2][size_t(k)];
          // Vertex normals that cancel out (a fold) fall back to the face, then to the heaviest vertex.
          if (normalise(m)) n = m;
          else if (!has_face) n = vn[l0 >= l1 && l0 >= l2 ? 0 : (l1 >= l2 ? 1 : 2)];
        }
        for (int k = 0; k < 3; ++k) out.normals[i * 3 + size_t(k)] = float(n[size_t(k)]);
      }
    }
  }
  return out;
}

}  // namespace ahd
