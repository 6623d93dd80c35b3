// Godot 4 primitive meshes with their UV2 (godot_primitives.h).
//
// Facts from Godot 4.6, scene/resources/3d/primitive_meshes.cpp/.h (read, not copied): each type's
// _create_mesh_array (vertex order, normals, UV2 charts), _update_lightmap_size (the hint),
// PrimitiveMesh::_update (flip_faces; the UV2 fallback uv * get_uv2_scale() used by PlaneMesh and
// QuadMesh, which write no UV2 themselves), the setters' clamps and the defaults in the header.
//
// Precision: Godot keeps every value in a `float` (real_t) but writes its constants as doubles
// (2.0, 0.5, Math::PI, Math::TAU), so a C++ expression mixing them is evaluated in double and
// rounded when stored. The code below spells each of those roundings out (f(...) = to float), and
// accumulated coordinates (x += size.x / (n + 1.0)) are accumulated the same way, not recomputed
// as i * step: the result equals Godot 4.6's arrays bit for bit (positions, normals after their
// 16-bit octahedral storage, UV2; measured on tests/data/godot/generated/primitives.json).
//
// 4.x history, for older scenes: a pre-4.5 copy of this code (Math_PI era) computed the seam
// column as sin/cos(TAU) instead of exactly (0, 1) (equal after rounding to float) and a sphere's
// normal as (x w scale, radius cos, z w scale) normalised, which differs from 4.6's unless the
// radius is 1; the UV2 charts, padding and lightmap size hints were the same formulas.
#include "bakers/godot/godot_primitives.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <functional>
#include <type_traits>
#include <utility>
#include <vector>

#include "ahd/types.h"

namespace ahd {
namespace {

constexpr double kPi = 3.1415926535897932384626433833;   // Godot's Math::PI
constexpr double kTau = 6.2831853071795864769252867666;  // Godot's Math::TAU
constexpr float kCmpEpsilon = 0.00001f;                  // Godot's CMP_EPSILON
constexpr double kPaddingRefSize = 1024.0;               // PADDING_REF_SIZE, primitive_meshes.cpp
constexpr int64_t kMaxVertices = int64_t(1) << 22;
constexpr int64_t kMaxInt = 1000000;

inline float f(double v) { return static_cast<float>(v); }
// sinf/cosf, correctly rounded (see TorusMesh).
inline float fsin(float a) { return f(std::sin(double(a))); }
inline float fcos(float a) { return f(std::cos(double(a))); }

struct V2 {
  float x = 0, y = 0;
};
struct V3 {
  float x = 0, y = 0, z = 0;
};

// Vector3::normalized (core/math/vector3.h): float length, zero stays zero.
V3 normalized(V3 v) {
  const float l2 = v.x * v.x + v.y * v.y + v.z * v.z;
  if (l2 == 0.0f) return V3{};
  const float l = std::sqrt(l2);
  return V3{v.x / l, v.y / l, v.z / l};
}

// Math::is_equal_approx(float, float) (core/math/math_funcs.h): a setter returns early when the new
// value is "equal", keeping the old one exactly.
bool equal_approx(float a, float b) {
  if (a == b) return true;
  float tolerance = kCmpEpsilon * std::fabs(a);
  if (tolerance < kCmpEpsilon) tolerance = kCmpEpsilon;
  return std::fabs(a - b) < tolerance;
}
bool equal_approx(V3 a, V3 b) { return equal_approx(a.x, b.x) && equal_approx(a.y, b.y) && equal_approx(a.z, b.z); }

// Godot's MAX(double, float) then the store into Vector2i's int32 (truncation). Bounded first: a
// double outside int's range has no defined conversion.
int hint_int(double v, const std::string& source, const std::string& type) {
  if (!(v > -2147483648.0 && v < 2147483648.0))
    throw Error(source + ": " + type + " is too large: its lightmap size hint is out of range");
  return static_cast<int>(v);
}

// ---- property text ----------------------------------------------------------------------------

std::string trim(const std::string& s) {
  size_t b = 0, e = s.size();
  while (b < e && (s[b] == ' ' || s[b] == '\t' || s[b] == '\r')) ++b;
  while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t' || s[e - 1] == '\r')) --e;
  return s.substr(b, e - b);
}

class Props {
 public:
  Props(const std::map<std::string, std::string>& m, const std::string& source, const std::string& type)
      : m_(m), source_(source), type_(type) {}

  [[noreturn]] void fail(const std::string& name, const std::string& cause) const {
    throw Error(source_ + ": " + type_ + " " + name + ": " + cause);
  }
  const std::string* raw(const std::string& name) const {
    auto it = m_.find(name);
    return it == m_.end() ? nullptr : &it->second;
  }

  // A number as Godot's parser reads it (a double), then stored in a float property.
  static bool number(const std::string& text, double& out) {
    const std::string t = trim(text);
    if (t.empty()) return false;
    const char* b = t.data();
    const char* e = t.data() + t.size();
    if (*b == '+') ++b;
    auto r = std::from_chars(b, e, out, std::chars_format::general);
    return r.ec == std::errc() && r.ptr == e && std::isfinite(out);
  }
  bool get_float(const std::string& name, float& out) const {
    const std::string* t = raw(name);
    if (!t) return false;
    double v = 0;
    if (!number(*t, v)) fail(name, "'" + *t + "' is not a finite number");
    if (!std::isfinite(f(v))) fail(name, "'" + *t + "' does not fit a float");
    out = f(v);
    return true;
  }
  bool get_int(const std::string& name, int& out) const {
    const std::string* t = raw(name);
    if (!t) return false;
    const std::string s = trim(*t);
    long long v = 0;
    const char* b = s.data();
    const char* e = s.data() + s.size();
    if (b != e && *b == '+') ++b;
    auto r = std::from_chars(b, e, v);
    if (s.empty() || r.ec != std::errc() || r.ptr != e) fail(name, "'" + *t + "' is not an integer");
    if (v < -kMaxInt || v > kMaxInt) fail(name, "'" + *t + "' is out of range (|n| <= 1000000)");
    out = static_cast<int>(v);
    return true;
  }
  bool get_bool(const std::string& name, bool& out) const {
    const std::string* t = raw(name);
    if (!t) return false;
    const std::string s = trim(*t);
    if (s == "true") {
      out = true;
    } else if (s == "false") {
      out = false;
    } else {
      fail(name, "'" + *t + "' is not true or false");
    }
    return true;
  }
  // "Vector3(4, 0.2, 4)" / "Vector2(1, 1)": n finite numbers.
  bool get_vector(const std::string& name, int n, float* out) const {
    const std::string* t = raw(name);
    if (!t) return false;
    const std::string s = trim(*t);
    const std::string head = n == 3 ? "Vector3(" : "Vector2(";
    const std::string shape = n == 3 ? "Vector3(x, y, z)" : "Vector2(x, y)";
    if (s.rfind(head, 0) != 0 || s.back() != ')') fail(name, "'" + *t + "' is not " + shape);
    const std::string body = s.substr(head.size(), s.size() - head.size() - 1);
    size_t start = 0;
    for (int k = 0; k < n; ++k) {
      const size_t comma = body.find(',', start);
      if ((k < n - 1) != (comma != std::string::npos)) fail(name, "'" + *t + "' is not " + shape);
      const std::string part = body.substr(start, k < n - 1 ? comma - start : std::string::npos);
      double v = 0;
      if (!number(part, v) || !std::isfinite(f(v))) fail(name, "'" + *t + "' is not " + shape + " of finite numbers");
      out[k] = f(v);
      start = comma + 1;
    }
    return true;
  }
  bool get_v3(const std::string& name, V3& out) const {
    float v[3];
    if (!get_vector(name, 3, v)) return false;
    out = V3{v[0], v[1], v[2]};
    return true;
  }
  bool get_v2(const std::string& name, V2& out) const {
    float v[2];
    if (!get_vector(name, 2, v)) return false;
    out = V2{v[0], v[1]};
    return true;
  }
  // A float property through its setter, which returns early on an equal_approx value: true when
  // `field` took the new value. equal_approx's tolerance scales with its first argument, so the
  // order is the setter's: new value first, or the old one where `old_first`.
  bool set_float(const std::string& name, float& field, bool old_first = false) const {
    float v;
    if (!get_float(name, v) || (old_first ? equal_approx(field, v) : equal_approx(v, field))) return false;
    field = v;
    return true;
  }
  bool set_v3(const std::string& name, V3& field) const {
    V3 v;
    if (!get_v3(name, v) || equal_approx(v, field)) return false;
    field = v;
    return true;
  }

 private:
  const std::map<std::string, std::string>& m_;
  const std::string& source_;
  const std::string& type_;
};

// ---- the arrays Godot builds --------------------------------------------------------------------

struct Arrays {
  std::vector<V3> points, normals;
  std::vector<V2> uv2;
  std::vector<int> indices;
  bool has_uv2 = false;  // false: PrimitiveMesh::_update's fallback (uv * uv2 scale) fills it
  std::vector<V2> uv;    // only kept for the fallback
  void add(V3 p, V3 n, V2 t2) {
    points.push_back(p);
    normals.push_back(n);
    uv2.push_back(t2);
  }
  void tri(int a, int b, int c) {
    indices.push_back(a);
    indices.push_back(b);
    indices.push_back(c);
  }
};

// The two triangles of a grid cell, as Godot's single-column grids write them.
void quad_single(Arrays& a, int prevrow, int thisrow, int i) {
  a.tri(prevrow + i - 1, prevrow + i, thisrow + i - 1);
  a.tri(prevrow + i, thisrow + i, thisrow + i - 1);
}
// The same for grids whose rows interleave two faces (BoxMesh, PrismMesh): `o` 0 = the first face,
// 1 = the second.
void quad_pair(Arrays& a, int prevrow, int thisrow, int i2, int o) {
  a.tri(prevrow + i2 - 2 + o, prevrow + i2 + o, thisrow + i2 - 2 + o);
  a.tri(prevrow + i2 + o, thisrow + i2 + o, thisrow + i2 - 2 + o);
}

// sin/cos of the seam column: Godot writes exactly (0, 1) at i == segments.
void ring_dir(int i, int segments, float u, float& s, float& c) {
  if (i == segments) {
    s = 0.0f;
    c = 1.0f;
  } else {
    s = f(std::sin(double(u) * kTau));
    c = f(std::cos(double(u) * kTau));
  }
}

// i / (n + 1.0) rounded to float: a grid line's UV along n subdivisions.
inline float frac(int i, int n) { return f(double(i) / (n + 1.0)); }
// Godot's accumulated grid coordinate, x += length / (n + 1.0) in a float: the sum in double, rounded.
inline float step(float x, float length, int n) { return f(x + double(length) / (n + 1.0)); }

// How a grid's cells become triangles: one face per row (quad_single), two interleaved faces
// (quad_pair), or two whose first row is a ridge of coincident points (PrismMesh's front and back:
// one triangle per face in the first band).
enum class Cells { single, pair, ridge_pair };

// Godot's grid loops: rows j = 0..rows, columns i = 0..cols. `row(j)` starts each row, `column(i)`
// writes the column's vertices (one, or two for the paired cells); the cells' triangles follow.
// `point` counts the vertices written so far: each grid starts a fresh thisrow = point, prevrow = 0.
template <class Row, class Column>
void grid(Arrays& a, int& point, int rows, int cols, Cells cells, Row row, Column column) {
  int thisrow = point, prevrow = 0;
  for (int j = 0; j <= rows; ++j) {
    row(j);
    for (int i = 0; i <= cols; ++i) {
      column(i);
      point += cells == Cells::single ? 1 : 2;
      if (i == 0 || j == 0) continue;
      const int i2 = i * 2;
      if (cells == Cells::single) {
        quad_single(a, prevrow, thisrow, i);
      } else if (cells == Cells::ridge_pair && j == 1) {
        a.tri(prevrow + i2, thisrow + i2, thisrow + i2 - 2);
        a.tri(prevrow + i2 + 1, thisrow + i2 + 1, thisrow + i2 - 1);
      } else {
        quad_pair(a, prevrow, thisrow, i2, 0);
        quad_pair(a, prevrow, thisrow, i2, 1);
      }
    }
    prevrow = thisrow;
    thisrow = point;
  }
}

// An axis a face grid walks in a float: from `start`, step(…, length, n) per grid line, n the
// subdivisions.
struct Walk {
  float start, length;
  int n;
};

// The face grids (BoxMesh, PlaneMesh, PrismMesh): the rows walk `down`, each row's columns walk
// `across` from its start again, and `column(x, y, u2, v2)` writes a column's vertices with
// u2 = frac(i, across.n), v2 = frac(j, v_n) (v_n is down.n but on BoxMesh's front, see there).
template <class Column>
void face_grid(Arrays& a, int& point, Cells cells, Walk down, Walk across, int v_n, Column column) {
  float x = 0, y = 0, v2 = 0;
  grid(
      a, point, down.n + 1, across.n + 1, cells,
      [&](int j) {
        y = j == 0 ? down.start : step(y, down.length, down.n);
        v2 = frac(j, v_n);
        x = across.start;
      },
      [&](int i) {
        column(x, y, frac(i, across.n), v2);
        x = step(x, across.length, across.n);
      });
}

// The ring grids (CapsuleMesh, CylinderMesh, SphereMesh): `row(j, v)` with v = j / rows, then
// `column(u, s, c)` round the ring, u = i / segments and (s, c) its ring_dir.
template <class Row, class Column>
void ring_grid(Arrays& a, int& point, int rows, int segments, Row row, Column column) {
  grid(
      a, point, rows, segments, Cells::single, [&](int j) { row(j, float(j) / float(rows)); },
      [&](int i) {
        const float u = float(i) / float(segments);
        float s, c;
        ring_dir(i, segments, u, s, c);
        column(u, s, c);
      });
}

struct Common {
  bool flip_faces = false;
  bool add_uv2 = false;
  float uv2_padding = 2.0f;
  float texel_size = 0.2f;
  std::array<int, 2> hint{0, 0};
  std::string source, type;
  int hint_int(double v) const { return ahd::hint_int(v, source, type); }
};

// ---- CapsuleMesh -------------------------------------------------------------------------------

struct Capsule {
  float radius = 0.5f, height = 2.0f;
  int radial_segments = 64, rings = 8;

  void update_hint(Common& c) const {
    if (!c.add_uv2) return;
    const float padding = c.uv2_padding;
    const float radial_length = f(double(radius) * kPi * 0.5);
    const float vertical_length = f(double(radial_length * 2) + (double(height) - 2.0 * radius));
    c.hint[0] = c.hint_int(std::max(1.0, 4.0 * radial_length / c.texel_size) + padding);
    c.hint[1] = c.hint_int(std::max(1.0, double(vertical_length / c.texel_size)) + padding);
  }
  void set(const Props& p, Common& c) {
    int n;
    if (p.set_float("radius", radius, true)) {
      if (radius > double(height) * 0.5) height = f(double(radius) * 2.0);
      update_hint(c);
    }
    if (p.set_float("height", height, true)) {
      if (radius > double(height) * 0.5) radius = f(double(height) * 0.5);
      update_hint(c);
    }
    if (p.get_int("radial_segments", n) && n != radial_segments) radial_segments = n > 4 ? n : 4;
    if (p.get_int("rings", n) && n != rings && n >= 0) rings = n;
  }
  int64_t vertex_count() const { return int64_t(rings + 2) * (radial_segments + 1) * 3; }

  void build(Arrays& a, float pad) const {
    const float radial_width = f(2.0 * radius * kPi);
    const float radial_h = radial_width / (radial_width + pad);
    const float radial_length = f(double(radius) * kPi * 0.5);
    const float vertical_length = f(double(radial_length * 2) + (double(height) - 2.0 * radius) + pad);
    const float radial_v = radial_length / vertical_length;
    const float height_v = f((double(height) - 2.0 * radius) / vertical_length);
    int point = 0;
    float v = 0, w = 0, y = 0;

    // The hemispheres: the top one from the pole down, the bottom one from the rim down.
    auto hemisphere = [&](bool top) {
      const float oy = top ? f(0.5 * height - radius) : f(-0.5 * height + radius);
      ring_grid(
          a, point, rings + 1, radial_segments,
          [&](int j, float vj) {
            v = vj;
            const bool last = j == rings + 1;
            if (top) {
              w = last ? 1.0f : f(std::sin(0.5 * kPi * v));
              y = last ? 0.0f : f(std::cos(0.5 * kPi * v));
            } else {
              w = last ? 0.0f : f(std::cos(0.5 * kPi * v));
              y = last ? -1.0f : f(-std::sin(0.5 * kPi * v));
            }
          },
          [&](float u, float s, float co) {
            const float x = -s, z = co;
            const V3 q{x * w, y, -z * w};
            a.add(V3{q.x * radius + 0.0f, q.y * radius + oy, q.z * radius + 0.0f}, q,
                  V2{u * radial_h, top ? v * radial_v : radial_v + height_v + v * radial_v});
          });
    };
    hemisphere(true);
    // Cylinder.
    ring_grid(
        a, point, rings + 1, radial_segments,
        [&](int, float vj) {
          v = vj;
          y = f((double(height) - 2.0 * radius) * v);
          y = f((0.5 * height - radius) - y);
        },
        [&](float u, float s, float co) {
          const float x = -s, z = co;
          a.add(V3{x * radius, y, -z * radius}, V3{x, 0.0f, -z}, V2{u * radial_h, radial_v + (v * height_v)});
        });
    hemisphere(false);
    a.has_uv2 = true;
  }
};

// ---- BoxMesh -----------------------------------------------------------------------------------

// BoxMesh's and PrismMesh's hint: charts in two columns (width, depth) and three rows (the height
// twice, then `bottom`), padded between.
void box_hint(Common& c, V3 size, float bottom) {
  if (!c.add_uv2) return;
  const float padding = c.uv2_padding;
  const float width = (size.x + size.z) / c.texel_size;
  const float length = (size.y + size.y + bottom) / c.texel_size;
  c.hint[0] = c.hint_int(std::max(1.0, double(width)) + 2.0 * padding);
  c.hint[1] = c.hint_int(std::max(1.0, double(length)) + 3.0 * padding);
}

struct Box {
  V3 size{1, 1, 1};
  int sw = 0, sh = 0, sd = 0;

  void update_hint(Common& c) const { box_hint(c, size, std::max(size.x, size.z)); }
  void set(const Props& p, Common& c) {
    int n;
    if (p.set_v3("size", size)) update_hint(c);
    if (p.get_int("subdivide_width", n) && n != sw) sw = n > 0 ? n : 0;
    if (p.get_int("subdivide_height", n) && n != sh) sh = n > 0 ? n : 0;
    if (p.get_int("subdivide_depth", n) && n != sd) sd = n > 0 ? n : 0;
  }
  int64_t vertex_count() const {
    return 2 * (int64_t(sh + 2) * (sw + 2) + int64_t(sh + 2) * (sd + 2) + int64_t(sd + 2) * (sw + 2));
  }

  void build(Arrays& a, float pad) const {
    const float total_h = f(double(size.x + size.z) + 2.0 * pad);
    const float padding_h = pad / total_h;
    const float width_h = size.x / total_h;
    const float depth_h = size.z / total_h;
    const float total_v = f(double(size.y + size.y + std::max(size.x, size.z)) + 3.0 * pad);
    const float padding_v = pad / total_v;
    const float width_v = size.x / total_v;
    const float height_v = size.y / total_v;
    const float depth_v = size.z / total_v;
    const V3 start{size.x * -0.5f, size.y * -0.5f, size.z * -0.5f};
    const Walk across_x{start.x, size.x, sw}, down_y{start.y, size.y, sh}, z_walk{start.z, size.z, sd};
    int point = 0;

    // Front + back. (Godot divides the rows' v2 by subdivide_width + 1 here, not by
    // subdivide_height + 1: kept, so its charts are reproduced as they are.)
    face_grid(a, point, Cells::pair, down_y, across_x, sw, [&](float x, float y, float u2, float v2) {
      a.add(V3{x, -y, -start.z}, V3{0, 0, 1}, V2{u2 * width_h, v2 * height_v});
      a.add(V3{-x, -y, start.z}, V3{0, 0, -1}, V2{u2 * width_h, height_v + padding_v + (v2 * height_v)});
    });
    // Right + left.
    face_grid(a, point, Cells::pair, down_y, z_walk, sh, [&](float z, float y, float u2, float v2) {
      a.add(V3{-start.x, -y, -z}, V3{1, 0, 0}, V2{width_h + padding_h + (u2 * depth_h), v2 * height_v});
      a.add(V3{start.x, -y, z}, V3{-1, 0, 0},
            V2{width_h + padding_h + (u2 * depth_h), height_v + padding_v + (v2 * height_v)});
    });
    // Top + bottom.
    const double row = double(height_v + padding_v) * 2.0;
    face_grid(a, point, Cells::pair, z_walk, across_x, sd, [&](float x, float z, float u2, float v2) {
      a.add(V3{-x, -start.y, -z}, V3{0, 1, 0}, V2{u2 * width_h, f(row + (v2 * depth_v))});
      a.add(V3{x, start.y, -z}, V3{0, -1, 0}, V2{width_h + padding_h + (u2 * depth_h), f(row + (v2 * width_v))});
    });
    a.has_uv2 = true;
  }
};

// ---- CylinderMesh ------------------------------------------------------------------------------

struct Cylinder {
  float top_radius = 0.5f, bottom_radius = 0.5f, height = 2.0f;
  int radial_segments = 64, rings = 4;
  bool cap_top = true, cap_bottom = true;

  void update_hint(Common& c) const {
    if (!c.add_uv2) return;
    const float padding = c.uv2_padding;
    const float top_c = f(double(top_radius) * kPi * 2.0);
    const float bottom_c = f(double(bottom_radius) * kPi * 2.0);
    float width = std::max(top_c, bottom_c) / c.texel_size + padding;
    width = f(std::max(double(width), double(((top_radius + bottom_radius) / c.texel_size) + padding) * 2.0));
    c.hint[0] = c.hint_int(std::max(1.0, double(width)));
    const float hgt =
        f(((double(height) + (double(std::max(top_radius, bottom_radius)) * 2.0)) / c.texel_size) + (2.0 * padding));
    c.hint[1] = c.hint_int(std::max(1.0, double(hgt)));
  }
  void set(const Props& p, Common& c) {
    int n;
    bool b;
    if (p.set_float("top_radius", top_radius)) update_hint(c);
    if (p.set_float("bottom_radius", bottom_radius)) update_hint(c);
    if (p.set_float("height", height)) update_hint(c);
    if (p.get_int("radial_segments", n) && n != radial_segments) radial_segments = n > 4 ? n : 4;
    if (p.get_int("rings", n) && n != rings && n >= 0) rings = n;
    if (p.get_bool("cap_top", b)) cap_top = b;
    if (p.get_bool("cap_bottom", b)) cap_bottom = b;
  }
  int64_t vertex_count() const { return int64_t(rings + 2) * (radial_segments + 1) + 2 * int64_t(radial_segments + 2); }

  void build(Arrays& a, float pad) const {
    const float top_circumference = f(double(top_radius) * kPi * 2.0);
    const float bottom_circumference = f(double(bottom_radius) * kPi * 2.0);
    const float vertical_length = f(double(height) + std::max(2.0 * top_radius, 2.0 * bottom_radius) + (2.0 * pad));
    const float height_v = height / vertical_length;
    const float padding_v = pad / vertical_length;
    const double h1 = 2.0 * double(top_radius + bottom_radius + pad);
    const float horizontal_length =
        f(std::max(std::max(h1, double(top_circumference + pad)), double(bottom_circumference + pad)));
    const float center_h = f(0.5 * double(horizontal_length - pad) / horizontal_length);
    float top_h = top_circumference / horizontal_length;
    float bottom_h = bottom_circumference / horizontal_length;
    const float padding_h = pad / horizontal_length;
    const float side_normal_y = (bottom_radius - top_radius) / height;
    int point = 0;

    float v = 0, radius = 0, radius_h = 0, y = 0;
    ring_grid(
        a, point, rings + 1, radial_segments,
        [&](int, float vj) {
          v = vj;
          radius = top_radius + ((bottom_radius - top_radius) * v);
          radius_h = top_h + ((bottom_h - top_h) * v);
          y = height * v;
          y = f((double(height) * 0.5) - y);
        },
        [&](float u, float x, float z) {
          a.add(V3{x * radius, y, z * radius}, normalized(V3{x, side_normal_y, z}),
                V2{f(center_h + (double(u) - 0.5) * radius_h), v * height_v});
        });

    top_h = top_radius / horizontal_length;
    const float top_v = top_radius / vertical_length;
    bottom_h = bottom_radius / horizontal_length;
    const float bottom_v = bottom_radius / vertical_length;
    const float cap_v = height_v + padding_v + std::max(top_v, bottom_v);

    // A cap: its centre, then a fan round the rim (the bottom one wound the other way, its chart
    // mirrored in v).
    auto cap = [&](bool top, float cap_radius, float cy, float cx, float cap_h, float cap_uv_v) {
      const V3 normal{0, top ? 1.0f : -1.0f, 0};
      const int centre = point;
      a.add(V3{0, cy, 0}, normal, V2{cx, cap_v});
      ++point;
      for (int i = 0; i <= radial_segments; ++i) {
        const float r = float(i) / float(radial_segments);
        float x, z;
        ring_dir(i, radial_segments, r, x, z);
        a.add(V3{x * cap_radius, cy, z * cap_radius}, normal,
              V2{cx + (x * cap_h), top ? cap_v + (z * cap_uv_v) : cap_v - (z * cap_uv_v)});
        ++point;
        if (i > 0 && top) a.tri(centre, point - 1, point - 2);
        if (i > 0 && !top) a.tri(centre, point - 2, point - 1);
      }
    };
    if (cap_top && top_radius > 0.0f) cap(true, top_radius, f(double(height) * 0.5), top_h, top_h, top_v);
    if (cap_bottom && bottom_radius > 0.0f)
      cap(false, bottom_radius, f(double(height) * -0.5), top_h + top_h + padding_h + bottom_h, bottom_h, bottom_v);
    a.has_uv2 = true;
  }
};

// ---- PlaneMesh / QuadMesh ----------------------------------------------------------------------

struct Plane {
  V2 size{2, 2};
  int sw = 0, sd = 0;
  V3 center_offset{};
  int orientation = 1;  // FACE_X 0, FACE_Y 1, FACE_Z 2

  void update_hint(Common& c) const {
    if (!c.add_uv2) return;
    const float padding = c.uv2_padding;
    c.hint[0] = c.hint_int(std::max(1.0, double((size.x / c.texel_size) + padding)));
    c.hint[1] = c.hint_int(std::max(1.0, double((size.y / c.texel_size) + padding)));
  }
  void set(const Props& p, Common& c) {
    V2 s;
    int n;
    if (p.get_v2("size", s) && !(s.x == size.x && s.y == size.y)) {
      size = s;
      update_hint(c);
    }
    if (p.get_int("subdivide_width", n) && !(n == sw || (sw == 0 && n < 0))) sw = n > 0 ? n : 0;
    if (p.get_int("subdivide_depth", n) && !(n == sd || (sd == 0 && n < 0))) sd = n > 0 ? n : 0;
    p.set_v3("center_offset", center_offset);
    if (p.get_int("orientation", n)) {
      if (n < 0 || n > 2) p.fail("orientation", std::to_string(n) + " is not 0 (Face X), 1 (Face Y) or 2 (Face Z)");
      orientation = n;
    }
  }
  int64_t vertex_count() const { return int64_t(sd + 2) * (sw + 2); }

  void build(Arrays& a) const {
    const V2 start{size.x * -0.5f, size.y * -0.5f};
    V3 normal{0, 1, 0};
    if (orientation == 0) normal = V3{1, 0, 0};
    if (orientation == 2) normal = V3{0, 0, 1};
    const V3& co = center_offset;
    int point = 0;
    face_grid(a, point, Cells::single, Walk{start.y, size.y, sd}, Walk{start.x, size.x, sw}, sd,
              [&](float x, float z, float u, float v) {
                V3 pt;
                if (orientation == 0) {
                  pt = V3{0.0f + co.x, z + co.y, x + co.z};
                } else if (orientation == 1) {
                  pt = V3{-x + co.x, 0.0f + co.y, -z + co.z};
                } else {
                  pt = V3{-x + co.x, z + co.y, 0.0f + co.z};
                }
                a.points.push_back(pt);
                a.normals.push_back(normal);
                a.uv.push_back(V2{f(1.0 - u), f(1.0 - v)});
              });
    a.has_uv2 = false;
  }
};

// ---- PrismMesh ---------------------------------------------------------------------------------

struct Prism {
  float left_to_right = 0.5f;
  V3 size{1, 1, 1};
  int sw = 0, sh = 0, sd = 0;

  void update_hint(Common& c) const { box_hint(c, size, size.z); }
  void set(const Props& p, Common& c) {
    int n;
    p.set_float("left_to_right", left_to_right);
    if (p.set_v3("size", size)) update_hint(c);
    if (p.get_int("subdivide_width", n) && !(n == sw || (n < 0 && sw == 0))) sw = n > 0 ? n : 0;
    if (p.get_int("subdivide_height", n) && !(n == sh || (n < 0 && sh == 0))) sh = n > 0 ? n : 0;
    if (p.get_int("subdivide_depth", n) && !(n == sd || (n < 0 && sd == 0))) sd = n > 0 ? n : 0;
  }
  int64_t vertex_count() const {
    return 2 * int64_t(sh + 2) * (sw + 2) + 2 * int64_t(sh + 2) * (sd + 2) + int64_t(sd + 2) * (sw + 2);
  }

  void build(Arrays& a, float pad) const {
    const float horizontal_total = f(double(size.x + size.z) + 2.0 * pad);
    const float width_h = size.x / horizontal_total;
    const float depth_h = size.z / horizontal_total;
    const float padding_h = pad / horizontal_total;
    const float vertical_total = f(double(size.y + size.y + size.z) + (3.0 * pad));
    const float height_v = size.y / vertical_total;
    const float depth_v = size.z / vertical_total;
    const float padding_v = pad / vertical_total;
    const V3 start{size.x * -0.5f, size.y * -0.5f, size.z * -0.5f};
    const double ltr = left_to_right;
    int point = 0;
    float x = 0, y = 0, scale = 0, v2 = 0;

    // Front + back: row 0 is the ridge, every column's points there coincide.
    float scaled_size_x = 0, start_x = 0;
    grid(
        a, point, sh + 1, sw + 1, Cells::ridge_pair,
        [&](int j) {
          y = j == 0 ? start.y : step(y, size.y, sh);
          scale = frac(j, sh);
          scaled_size_x = size.x * scale;
          start_x = f(start.x + (1.0 - scale) * size.x * ltr);
          v2 = scale;
          x = 0.0f;
        },
        [&](int i) {
          const float u2 = frac(i, sw);
          a.add(V3{start_x + x, -y, -start.z}, V3{0, 0, 1}, V2{u2 * scale * width_h, v2 * height_v});
          a.add(V3{start_x + scaled_size_x - x, -y, start.z}, V3{0, 0, -1},
                V2{u2 * scale * width_h, height_v + padding_v + v2 * height_v});
          x = step(x, scale * size.x, sw);
        });

    // Right + left: the slanted sides.
    const V3 normal_left = normalized(V3{-size.y, f(double(size.x) * ltr), 0.0f});
    const V3 normal_right = normalized(V3{size.y, f(double(size.x) * (1.0 - ltr)), 0.0f});
    const Walk z_walk{start.z, size.z, sd};
    face_grid(a, point, Cells::pair, Walk{start.y, size.y, sh}, z_walk, sh, [&](float z, float y, float u2, float v2) {
      const float left = f(start.x + (double(size.x) * (1.0 - v2) * ltr));  // v2 is the row's scale
      const float right = left + (size.x * v2);
      a.add(V3{right, -y, -z}, normal_right, V2{width_h + padding_h + u2 * depth_h, v2 * height_v});
      a.add(V3{left, -y, z}, normal_left, V2{width_h + padding_h + u2 * depth_h, height_v + padding_v + v2 * height_v});
    });

    // Bottom.
    face_grid(
        a, point, Cells::single, z_walk, Walk{start.x, size.x, sw}, sd, [&](float x, float z, float u2, float v2) {
          a.add(V3{x, start.y, -z}, V3{0, -1, 0}, V2{u2 * width_h, f(2.0 * (height_v + padding_v) + v2 * depth_v)});
        });
    a.has_uv2 = true;
  }
};

// ---- SphereMesh --------------------------------------------------------------------------------

struct Sphere {
  float radius = 0.5f, height = 1.0f;
  int radial_segments = 64, rings = 32;
  bool is_hemisphere = false;

  void update_hint(Common& c) const {
    if (!c.add_uv2) return;
    const float padding = c.uv2_padding;
    const float width = f(double(radius) * kTau);
    c.hint[0] = c.hint_int(std::max(1.0, double((width / c.texel_size) + padding)));
    const float hgt = f((is_hemisphere ? 1.0 : 0.5) * height * kPi);
    c.hint[1] = c.hint_int(std::max(1.0, double((hgt / c.texel_size) + padding)));
  }
  void set(const Props& p, Common& c) {
    int n;
    bool b;
    if (p.set_float("radius", radius)) update_hint(c);
    if (p.set_float("height", height, true)) update_hint(c);
    if (p.get_int("radial_segments", n) && !(n == radial_segments || (radial_segments == 4 && n < 4)))
      radial_segments = n > 4 ? n : 4;
    if (p.get_int("rings", n) && n != rings && n >= 1) rings = n;
    if (p.get_bool("is_hemisphere", b) && b != is_hemisphere) {
      is_hemisphere = b;
      update_hint(c);
    }
  }
  int64_t vertex_count() const { return int64_t(rings + 2) * (radial_segments + 1); }

  void build(Arrays& a, float pad) const {
    const float scale = f(double(height / radius) * (is_hemisphere ? 1.0 : 0.5));
    const float circumference = f(double(radius) * kTau);
    const float horizontal_length = circumference + pad;
    const float center_h = f(0.5 * circumference / horizontal_length);
    const float height_v = f(scale * kPi / ((scale * kPi) + double(pad / radius)));
    int point = 0;
    float v = 0, w = 0, y = 0;
    ring_grid(
        a, point, rings + 1, radial_segments,
        [&](int j, float vj) {
          v = vj;
          w = j == rings + 1 ? 0.0f : f(std::sin(kPi * v));
          y = j == rings + 1 ? -1.0f : f(std::cos(kPi * v));
        },
        [&](float u, float x, float z) {
          V3 pt, n;
          if (is_hemisphere && y < 0.0f) {
            pt = V3{x * radius * w, 0.0f, z * radius * w};
            n = V3{0, -1, 0};
          } else {
            const V3 q{x * w, y * scale, z * w};
            pt = V3{q.x * radius, q.y * radius, q.z * radius};
            n = normalized(V3{x * w * scale, y, z * w * scale});
          }
          const float w_h = f(double(w) * 2.0 * center_h);
          a.add(pt, n, V2{f(center_h + ((double(u) - 0.5) * w_h)), v * height_v});
        });
    a.has_uv2 = true;
  }
};

// ---- TorusMesh ---------------------------------------------------------------------------------

struct Torus {
  float inner_radius = 0.5f, outer_radius = 1.0f;
  int rings = 64, ring_segments = 32;

  // The radii in order, and the tube's radius.
  void radii(float& min_radius, float& max_radius, float& radius) const {
    min_radius = inner_radius;
    max_radius = outer_radius;
    if (min_radius > max_radius) std::swap(min_radius, max_radius);
    radius = f((max_radius - min_radius) * 0.5);
  }
  void update_hint(Common& c) const {
    if (!c.add_uv2) return;
    const float padding = c.uv2_padding;
    float min_radius, max_radius, radius;
    radii(min_radius, max_radius, radius);
    const float width = f(double(max_radius) * kTau);
    c.hint[0] = c.hint_int(std::max(1.0, double((width / c.texel_size) + padding)));
    const float hgt = f(double(radius) * kTau);
    c.hint[1] = c.hint_int(std::max(1.0, double((hgt / c.texel_size) + padding)));
  }
  // Godot's radius setters do not call _update_lightmap_size: the hint keeps the radii of the last
  // add_uv2 / uv2_padding change.
  void set(const Props& p, Common&) {
    int n;
    p.set_float("inner_radius", inner_radius);
    p.set_float("outer_radius", outer_radius);
    if (p.get_int("rings", n) && n != rings && n >= 3) rings = n;
    if (p.get_int("ring_segments", n) && n != ring_segments && n >= 3) ring_segments = n;
  }
  int64_t vertex_count() const { return int64_t(rings + 1) * (ring_segments + 1); }

  void build(Arrays& a, float pad, const Props& p) const {
    if (inner_radius == outer_radius) p.fail("inner_radius", "equals outer_radius: Godot builds no mesh");
    float min_radius, max_radius, radius;
    radii(min_radius, max_radius, radius);
    const float horizontal_total = f(double(max_radius) * kTau + pad);
    const float max_h = f(double(max_radius) * kTau / horizontal_total);
    const float delta_h = f(double(max_radius - min_radius) * kTau / horizontal_total);
    const float height_v = f(double(radius) * kTau / (double(radius) * kTau + pad));
    for (int i = 0; i <= rings; ++i) {
      const int prevrow = (i - 1) * (ring_segments + 1);
      const int thisrow = i * (ring_segments + 1);
      const float inci = float(i) / float(rings);
      const float angi = f(double(inci) * kTau);
      // Math::sin(float) is sinf of the float angle. glibc's sinf is 1 ulp off the correctly
      // rounded value at some of these angles (3/64 of a turn), where the Godot 4.6 fixture has
      // the correctly rounded one: take sin in double, rounded once.
      const V2 normali = i == rings ? V2{0.0f, -1.0f} : V2{-fsin(angi), -fcos(angi)};
      for (int j = 0; j <= ring_segments; ++j) {
        const float incj = float(j) / float(ring_segments);
        const float angj = f(double(incj) * kTau);
        const V2 normalj = j == ring_segments ? V2{-1.0f, 0.0f} : V2{-fcos(angj), fsin(angj)};
        const V2 normalk{normalj.x * radius + (min_radius + radius), normalj.y * radius + 0.0f};
        float offset_h = f(0.5 * (1.0 - normalj.x) * delta_h);
        const float adj_h = max_h - offset_h;
        offset_h = f(offset_h * 0.5);
        a.add(V3{normali.x * normalk.x, normalk.y, normali.y * normalk.x},
              V3{normali.x * normalj.x, normalj.y, normali.y * normalj.x},
              V2{offset_h + inci * adj_h, incj * height_v});
        if (i > 0 && j > 0) {
          a.tri(thisrow + j - 1, prevrow + j, prevrow + j - 1);
          a.tri(thisrow + j - 1, thisrow + j, prevrow + j);
        }
      }
    }
    a.has_uv2 = true;
  }
};

// The normal Godot hands back (RenderingServer's surface arrays, which LightmapGI bakes from):
// mesh_add_surface_from_arrays stores normals as two 16-bit octahedral coordinates
// (servers/rendering_server.cpp, Vector3::octahedron_encode/_decode in core/math/vector3.cpp), so
// the arrays read back differ from the computed unit vector by up to ~3e-5. A zero normal (a
// degenerate prism side) is kept as it is: Godot's encoding of it is undefined.
V3 stored_normal(V3 n) {
  const float l1 = std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z);
  if (!(l1 > 0.0f) || !std::isfinite(l1)) return n;
  const V3 q{n.x / l1, n.y / l1, n.z / l1};
  float ox, oy;
  if (q.z >= 0.0f) {
    ox = q.x;
    oy = q.y;
  } else {
    ox = (1.0f - std::fabs(q.y)) * (q.x >= 0.0f ? 1.0f : -1.0f);
    oy = (1.0f - std::fabs(q.x)) * (q.y >= 0.0f ? 1.0f : -1.0f);
  }
  ox = ox * 0.5f + 0.5f;
  oy = oy * 0.5f + 0.5f;
  auto quantise = [](float o) {
    const float t = o * 65535.0f;
    return static_cast<uint16_t>(t < 0.0f ? 0.0f : (t > 65535.0f ? 65535.0f : t));
  };
  const float dx = f(quantise(ox) / 65535.0), dy = f(quantise(oy) / 65535.0);
  const float fx = dx * 2.0f - 1.0f, fy = dy * 2.0f - 1.0f;
  V3 d{fx, fy, 1.0f - std::fabs(fx) - std::fabs(fy)};
  const float t = std::clamp(-d.z, 0.0f, 1.0f);
  d.x += d.x >= 0 ? -t : t;
  d.y += d.y >= 0 ? -t : t;
  return normalized(d);
}

// ---- driver ------------------------------------------------------------------------------------

// Applies the PrimitiveMesh properties (they come first in Godot's property order), then the type's.
template <class Shape>
void apply(Shape& shape, Common& c, const Props& p) {
  bool b;
  if (p.get_bool("flip_faces", b)) c.flip_faces = b;
  if (p.get_bool("add_uv2", b) && b != c.add_uv2) {
    c.add_uv2 = b;
    shape.update_hint(c);
  }
  if (p.set_float("uv2_padding", c.uv2_padding)) shape.update_hint(c);
  shape.set(p, c);
}

struct Built {
  Arrays arrays;
  Common common;
};

template <class Shape>
Built build_shape(Shape shape, const Props& p, Common c, bool need_mesh) {
  apply(shape, c, p);
  Built out;
  out.common = c;
  if (!need_mesh) return out;
  if (!c.add_uv2)
    throw Error(c.source + ": " + c.type + " has add_uv2 = false: Godot gives it no lightmap UVs (UV2) to bake into");
  if (shape.vertex_count() > kMaxVertices)
    throw Error(c.source + ": " + c.type + " would have " + std::to_string(shape.vertex_count()) +
                " vertices (more than 4194304): subdivisions, rings or segments too many");
  const float pad = c.uv2_padding * c.texel_size;
  if constexpr (std::is_same_v<Shape, Plane>) {
    shape.build(out.arrays);
  } else if constexpr (std::is_same_v<Shape, Torus>) {
    shape.build(out.arrays, pad, p);
  } else {
    shape.build(out.arrays, pad);
  }
  return out;
}

Built build_any(const std::string& type, const std::map<std::string, std::string>& props, const std::string& source,
                float texel_size, bool need_mesh) {
  Common c;
  c.source = source;
  c.type = type;
  // PrimitiveMesh's constructor: a texel size <= 0 is taken as 0.2.
  c.texel_size = texel_size > 0.0f && std::isfinite(texel_size) ? texel_size : 0.2f;
  const Props p(props, c.source, c.type);
  if (type == "BoxMesh") return build_shape(Box{}, p, c, need_mesh);
  if (type == "PlaneMesh") return build_shape(Plane{}, p, c, need_mesh);
  if (type == "QuadMesh") {
    Plane q;  // QuadMesh's constructor: orientation FACE_Z, size 1 x 1
    q.orientation = 2;
    q.size = V2{1, 1};
    return build_shape(q, p, c, need_mesh);
  }
  if (type == "PrismMesh") return build_shape(Prism{}, p, c, need_mesh);
  if (type == "CylinderMesh") return build_shape(Cylinder{}, p, c, need_mesh);
  if (type == "CapsuleMesh") return build_shape(Capsule{}, p, c, need_mesh);
  if (type == "SphereMesh") return build_shape(Sphere{}, p, c, need_mesh);
  if (type == "TorusMesh") return build_shape(Torus{}, p, c, need_mesh);
  throw Error(source + ": '" + type + "' is not a Godot primitive mesh this tool rebuilds");
}

}  // namespace

bool is_godot_primitive_mesh(const std::string& type) {
  return type == "BoxMesh" || type == "PlaneMesh" || type == "QuadMesh" || type == "PrismMesh" ||
         type == "CylinderMesh" || type == "CapsuleMesh" || type == "SphereMesh" || type == "TorusMesh";
}

MeshTriangles godot_primitive_mesh(const std::string& type, const std::map<std::string, std::string>& props,
                                   const std::string& source, float texel_size) {
  Built b = build_any(type, props, source, texel_size, true);
  Arrays& a = b.arrays;
  const Common& c = b.common;

  // PrimitiveMesh::_update: flip_faces negates the normals and swaps each triangle's first two
  // indices; a type that wrote no UV2 gets uv * get_uv2_scale() (padding over the hint in texels).
  if (c.flip_faces) {
    for (V3& n : a.normals) n = V3{-n.x, -n.y, -n.z};
    for (size_t i = 0; i + 2 < a.indices.size(); i += 3) std::swap(a.indices[i], a.indices[i + 1]);
  }
  if (!a.has_uv2) {
    const float lx = float(c.hint[0]), ly = float(c.hint[1]);
    const float sx = f(double(1.0f * c.uv2_padding) / (lx == 0.0f ? kPaddingRefSize : double(lx)));
    const float sy = f(double(1.0f * c.uv2_padding) / (ly == 0.0f ? kPaddingRefSize : double(ly)));
    const V2 scale{1.0f - sx, 1.0f - sy};
    a.uv2.clear();
    for (const V2& t : a.uv) a.uv2.push_back(V2{t.x * scale.x, t.y * scale.y});
  }

  MeshTriangles m;
  const size_t n = a.points.size();
  m.positions.reserve(n * 3);
  m.normals.reserve(n * 3);
  m.uv.reserve(n * 2);
  for (size_t i = 0; i < n; ++i) {
    const V3 &p = a.points[i], &q = a.normals[i];
    const V2& t = a.uv2[i];
    const float vals[8] = {p.x, p.y, p.z, q.x, q.y, q.z, t.x, t.y};
    for (float v : vals)
      if (!std::isfinite(v))
        throw Error(source + ": " + type +
                    " is degenerate: its positions, normals or UV2 are not finite (a zero size?)");
    m.positions.insert(m.positions.end(), {p.x, p.y, p.z});
    const V3 sn = stored_normal(q);
    m.normals.insert(m.normals.end(), {sn.x, sn.y, sn.z});
    m.uv.insert(m.uv.end(), {t.x, 1.0f - t.y});
  }
  m.indices.assign(a.indices.begin(), a.indices.end());
  return m;
}

std::array<int, 2> godot_primitive_lightmap_size_hint(const std::string& type,
                                                      const std::map<std::string, std::string>& props,
                                                      const std::string& source, float texel_size) {
  return build_any(type, props, source, texel_size, false).common.hint;
}

}  // namespace ahd
