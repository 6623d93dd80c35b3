#include "bakers/godot/godot_array_mesh.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/error.h"
#include "bakers/godot/godot_lmbake.h"

namespace ahd {

namespace {

// ---------------------------------------------------------------------------------------------
// The surface format (servers/rendering/rendering_server.h, ArrayType and ArrayFormat).
constexpr int kVertex = 0, kNormal = 1, kTangent = 2, kColor = 3, kTexUv = 4, kTexUv2 = 5, kCustom0 = 6, kCustom3 = 9,
              kBones = 10, kWeights = 11, kIndex = 12, kArrayMax = 13;
constexpr int kCustomBase = 13, kCustomBits = 3;  // ARRAY_FORMAT_CUSTOM_BASE, _BITS
constexpr uint64_t kFlag2dVertices = 1ull << 25, kFlag8BoneWeights = 1ull << 27, kFlagCompress = 1ull << 29;
constexpr int kVersionShift = 35;  // ARRAY_FLAG_FORMAT_VERSION_SHIFT; 8 bits of version
constexpr int kPrimitiveTriangles = 3;

struct Bytes {
  const uint8_t* data = nullptr;
  size_t size = 0;
  bool present = false;
};

// One entry of `_surfaces`, whichever file it came from.
struct Surface {
  bool has_format = false, has_primitive = false, has_vertex_count = false, has_aabb = false, has_index_count = false;
  uint64_t format = 0;
  int64_t primitive = 0, vertex_count = 0, index_count = 0;
  Bytes vertex, attribute, index;
  double aabb[6] = {0, 0, 0, 0, 0, 0};  // position, size
  double uv_scale[4] = {0, 0, 0, 0};
};

uint16_t u16_at(const uint8_t* p) { return uint16_t(p[0] | p[1] << 8); }
uint32_t u32_at(const uint8_t* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}
float f32_at(const uint8_t* p) {
  const uint32_t b = u32_at(p);
  float f;
  std::memcpy(&f, &b, 4);
  return f;
}

// Vector3::octahedron_decode (core/math/vector3.cpp) of a stored 16+16-bit pair, in Godot's float
// arithmetic so the normals are the ones Godot's mesh_surface_get_arrays returns.
void octahedron_decode(uint32_t packed, float n[3]) {
  const float ox = float(double(packed & 0xFFFF) / 65535.0), oy = float(double(packed >> 16) / 65535.0);
  const float fx = ox * 2.0f - 1.0f, fy = oy * 2.0f - 1.0f;
  float x = fx, y = fy;
  const float z = 1.0f - std::fabs(fx) - std::fabs(fy);
  const float t = std::clamp(-z, 0.0f, 1.0f);
  x += x >= 0 ? -t : t;
  y += y >= 0 ? -t : t;
  const float l2 = x * x + y * y + z * z;
  if (l2 == 0) {
    n[0] = n[1] = n[2] = 0;
    return;
  }
  const float l = std::sqrt(l2);
  n[0] = x / l, n[1] = y / l, n[2] = z / l;
}

// Compressed normals and tangents (Godot 4.2+, ARRAY_FLAG_COMPRESS_ATTRIBUTES) are a rotation: the
// octahedral axis in the normal slot and the angle in the position's fourth 16-bit word
// (_get_tbn_from_axis_angle, rendering_server.cpp). The normal is row 2 of
// Basis::set_axis_angle(axis, angle) (core/math/basis.cpp).
void normal_from_axis_angle(uint32_t packed_axis, uint16_t packed_angle, float n[3]) {
  float a[3];
  octahedron_decode(packed_axis, a);
  const float p = float(double(packed_angle) / 65535.0);
  const float angle = float(std::fabs(double(p) * 2.0 - 1.0) * 3.14159265358979323846);
  const float c = std::cos(angle), s = std::sin(angle), t = 1 - c;
  const float zz = a[2] * a[2];
  n[0] = a[0] * a[2] * t - a[1] * s;
  n[1] = a[1] * a[2] * t + a[0] * s;
  n[2] = zz + c * (1.0f - zz);
}

// Byte sizes and offsets of the arrays in their streams (mesh_surface_make_offsets_from_format):
// vertex stream = positions of all vertices, then normal+tangent of all vertices; attribute stream
// = colour, UV, UV2, custom 0..3 interleaved; skin stream = bones, weights interleaved.
struct Layout {
  size_t offset[kArrayMax] = {};
  uint32_t vertex_stride = 0, normal_stride = 0, attribute_stride = 0, skin_stride = 0;
};

Layout layout_of(uint64_t format, size_t vertex_count) {
  Layout l;
  uint32_t* accum = nullptr;
  const bool compress = format & kFlagCompress;
  const uint32_t bone_words = (format & kFlag8BoneWeights) ? 8 : 4;
  for (int i = 0; i < kArrayMax; ++i) {
    if (i == kVertex) accum = &l.vertex_stride;
    if (i == kNormal) accum = &l.normal_stride;
    if (i == kColor) accum = &l.attribute_stride;
    if (i == kBones) accum = &l.skin_stride;
    if (!(format & (1ull << i)) || i == kIndex) continue;
    uint32_t size = 0;
    if (i == kVertex) size = (format & kFlag2dVertices) ? 8 : compress ? 8 : 12;
    else if (i == kNormal || i == kColor) size = 4;
    else if (i == kTangent) size = compress ? 0 : 4;
    else if (i == kTexUv || i == kTexUv2) size = compress ? 4 : 8;
    else if (i >= kCustom0 && i <= kCustom3) {
      static const uint32_t kCustomSize[8] = {4, 4, 4, 8, 4, 8, 12, 16};  // ArrayCustomFormat
      const uint64_t type = (format >> (kCustomBase + kCustomBits * (i - kCustom0))) & 7;
      size = kCustomSize[type];
    } else if (i == kBones || i == kWeights) size = 2 * bone_words;
    l.offset[i] = *accum;
    if (i == kNormal || i == kTangent) l.offset[i] += size_t(l.vertex_stride) * vertex_count;
    *accum += size;
  }
  return l;
}

[[noreturn]] void fail(const std::string& source, const std::string& where, const std::string& cause) {
  throw file_error(source, where + cause);
}

// Appends one surface's triangles to `out` (positions, UV2 flipped to v up, normals into `normals`
// when the surface has them, `has_normals` set for each vertex).
void decode_surface(const Surface& s, const std::string& source, size_t number, MeshTriangles& out,
                    std::vector<float>& normals, std::vector<uint8_t>& has_normals) {
  const std::string where = "surface " + std::to_string(number) + ": ";
  if (!s.has_format || !s.has_primitive || !s.has_vertex_count || !s.vertex.present || !s.has_aabb)
    fail(source, where, "missing one of format, primitive, vertex_count, vertex_data, aabb");
  if (s.primitive != kPrimitiveTriangles)
    fail(source, where, "primitive " + std::to_string(s.primitive) + " is not read (only 3, triangles)");
  const uint64_t f = s.format;
  const uint64_t version = (f >> kVersionShift) & 0xFF;
  if (version > 1)
    fail(source, where, "surface format version " + std::to_string(version + 1) + " is newer than Godot 4.2's (2)");
  if (f >> (kVersionShift + 8)) fail(source, where, "unknown format bits " + std::to_string(f));
  if (f & kFlag2dVertices) fail(source, where, "a 2D mesh (2D vertices) has no lightmap");
  if (!(f & (1ull << kVertex))) fail(source, where, "no vertex positions");
  if (!(f & (1ull << kTexUv2)))
    fail(source, where,
         "no lightmap UV2: the surface has no UV2 array (enable Light Baking: Static Lightmaps / UV2 unwrap)");
  const bool compress = f & kFlagCompress;
  if (version == 0 && compress) fail(source, where, "compressed attributes in a Godot 4.0/4.1 (version 1) surface");
  if (compress && (f & (1ull << kTangent)) && !(f & (1ull << kNormal)))
    fail(source, where, "compressed tangents without normals");
  if (s.vertex_count <= 0 || s.vertex_count > int64_t(std::numeric_limits<uint32_t>::max()))
    fail(source, where, "vertex_count " + std::to_string(s.vertex_count));
  const size_t n = size_t(s.vertex_count);
  const Layout l = layout_of(f, n);
  const bool has_normal = f & (1ull << kNormal), has_tangent = f & (1ull << kTangent);

  // The vertex stream: 4.2+ (version 2) positions then normals+tangents; 4.0/4.1 (version 1)
  // one interleaved stream position, normal, tangent (fix_surface_compatibility).
  const size_t v1_stride = 12 + (has_normal ? 4 : 0) + (has_tangent ? 4 : 0);
  const size_t per_vertex = version == 0 ? v1_stride : size_t(l.vertex_stride) + l.normal_stride;
  if (s.vertex.size / per_vertex != n || s.vertex.size % per_vertex != 0)
    fail(source, where,
         "vertex_data holds " + std::to_string(s.vertex.size) + " bytes, not " + std::to_string(per_vertex) +
             " x vertex_count " + std::to_string(n));
  if (s.attribute.size / l.attribute_stride != n || s.attribute.size % l.attribute_stride != 0)
    fail(source, where,
         "attribute_data holds " + std::to_string(s.attribute.size) + " bytes, not " +
             std::to_string(l.attribute_stride) + " x vertex_count " + std::to_string(n));

  // Indices (16-bit up to 65536 vertices, else 32-bit) or none: the vertices in order.
  std::vector<uint32_t> idx;
  const bool indexed = f & (1ull << kIndex);
  if (indexed != s.index.present || (s.index.present && !s.has_index_count))
    fail(source, where, "index_data, index_count and the format's index flag disagree");
  if (indexed) {
    const size_t stride = n <= 65536 ? 2 : 4;
    if (s.index_count <= 0 || uint64_t(s.index_count) != s.index.size / stride || s.index.size % stride != 0)
      fail(source, where,
           "index_data holds " + std::to_string(s.index.size) + " bytes, not " + std::to_string(stride) +
               " x index_count " + std::to_string(s.index_count));
    idx.resize(size_t(s.index_count));
    for (size_t i = 0; i < idx.size(); ++i) {
      const uint8_t* p = s.index.data + i * stride;
      idx[i] = stride == 2 ? u16_at(p) : u32_at(p);
      if (idx[i] >= n)
        fail(source, where,
             "index " + std::to_string(idx[i]) + " out of range (vertex_count " + std::to_string(n) + ")");
    }
  } else {
    idx.resize(n);
    for (size_t i = 0; i < n; ++i) idx[i] = uint32_t(i);
  }
  if (idx.size() % 3 != 0) fail(source, where, std::to_string(idx.size()) + " indices: not whole triangles");

  const size_t base = out.positions.size() / 3;
  if (base + n > std::numeric_limits<uint32_t>::max()) fail(source, where, "more than 2^32 vertices in all");
  out.positions.resize((base + n) * 3);
  out.uv.resize((base + n) * 2);
  normals.resize((base + n) * 3, 0.0f);
  has_normals.resize(base + n, has_normal ? 1 : 0);

  // The AABB and UV scale as Godot holds them (real_t = float).
  float ap[3], as[3];
  for (int k = 0; k < 3; ++k) ap[k] = float(s.aabb[k]), as[k] = float(s.aabb[3 + k]);
  float uvs[4];
  bool uv_scaled = false;
  for (int k = 0; k < 4; ++k) uvs[k] = float(s.uv_scale[k]), uv_scaled |= !(std::fabs(uvs[k]) < 0.00001f);

  for (size_t i = 0; i < n; ++i) {
    float* pos = &out.positions[(base + i) * 3];
    float* nrm = &normals[(base + i) * 3];
    if (version == 0) {
      const uint8_t* p = s.vertex.data + i * v1_stride;
      for (int k = 0; k < 3; ++k) pos[k] = f32_at(p + 4 * k);
      if (has_normal) octahedron_decode(u32_at(p + 12), nrm);
    } else if (compress) {
      const uint8_t* p = s.vertex.data + l.offset[kVertex] + i * l.vertex_stride;
      for (int k = 0; k < 3; ++k) pos[k] = float(double(u16_at(p + 2 * k)) / 65535.0) * as[k] + ap[k];
      if (has_normal)
        normal_from_axis_angle(u32_at(s.vertex.data + l.offset[kNormal] + i * l.normal_stride), u16_at(p + 6), nrm);
    } else {
      const uint8_t* p = s.vertex.data + l.offset[kVertex] + i * l.vertex_stride;
      for (int k = 0; k < 3; ++k) pos[k] = f32_at(p + 4 * k);
      if (has_normal) octahedron_decode(u32_at(s.vertex.data + l.offset[kNormal] + i * l.normal_stride), nrm);
    }
    const uint8_t* a = s.attribute.data + l.offset[kTexUv2] + i * l.attribute_stride;
    float u, v;
    if (compress) {
      u = float(double(u16_at(a)) / 65535.0), v = float(double(u16_at(a + 2)) / 65535.0);
      if (uv_scaled) u = (u - 0.5f) * uvs[2], v = (v - 0.5f) * uvs[3];
    } else {
      u = f32_at(a), v = f32_at(a + 4);
    }
    out.uv[(base + i) * 2] = u;
    out.uv[(base + i) * 2 + 1] = 1.0f - v;
  }
  out.indices.reserve(out.indices.size() + idx.size());
  for (uint32_t k : idx) out.indices.push_back(uint32_t(base) + k);
}

MeshTriangles decode_surfaces(const std::vector<Surface>& surfaces, const std::string& source) {
  MeshTriangles out;
  std::vector<float> normals;
  std::vector<uint8_t> has_normals;
  for (size_t i = 0; i < surfaces.size(); ++i) decode_surface(surfaces[i], source, i, out, normals, has_normals);
  if (std::find(has_normals.begin(), has_normals.end(), 1) != has_normals.end()) out.normals = std::move(normals);
  return out;
}

// ---------------------------------------------------------------------------------------------
// Godot's text variant syntax (core/variant/variant_parser.cpp), the part resource files use.

struct TextValue {
  enum Kind : uint8_t { kNil, kBool, kInt, kReal, kString, kArray, kDict, kCall } kind = kNil;
  int64_t i = 0;
  double d = 0;
  std::string s;  // a string, or a constructor's name (AABB, SubResource, …)
  std::vector<TextValue>
      items;  // array items; dictionary keys and values alternating; constructor arguments that are not numbers
  std::vector<double> nums;    // a constructor's numeric arguments
  std::vector<uint8_t> bytes;  // PackedByteArray
  bool number() const { return kind == kInt || kind == kReal; }
  double as_double() const { return kind == kInt ? double(i) : d; }
};

class TextParser {
 public:
  TextParser(const std::string& t, const std::string& src, size_t from = 0) : t_(t), src_(src), at_(from) {}
  size_t at() const { return at_; }
  bool eof() {
    skip_space();
    return at_ >= t_.size();
  }
  char peek() {
    skip_space();
    return at_ < t_.size() ? t_[at_] : '\0';
  }
  void expect(char c) {
    if (peek() != c) fail(std::string("expected '") + c + "'");
    ++at_;
  }
  [[noreturn]] void fail(const std::string& why) const {
    const size_t line = 1 + size_t(std::count(t_.begin(), t_.begin() + std::min(at_, t_.size()), '\n'));
    throw file_error(src_, why + " (line " + std::to_string(line) + ")");
  }

  TextValue value(int depth = 0) {
    if (depth > 64) fail("values nested deeper than 64");
    TextValue v;
    const char c = peek();
    if (c == '[') {
      ++at_;
      v.kind = TextValue::kArray;
      while (peek() != ']') {
        v.items.push_back(value(depth + 1));
        if (peek() == ',') ++at_;
        else if (peek() != ']') fail("expected ',' or ']'");
      }
      ++at_;
    } else if (c == '{') {
      ++at_;
      v.kind = TextValue::kDict;
      while (peek() != '}') {
        v.items.push_back(value(depth + 1));
        expect(':');
        v.items.push_back(value(depth + 1));
        if (peek() == ',') ++at_;
        else if (peek() != '}') fail("expected ',' or '}'");
      }
      ++at_;
    } else if (c == '"' || ((c == '&' || c == '^') && at_ + 1 < t_.size() && t_[at_ + 1] == '"')) {
      if (c != '"') ++at_;
      v.kind = TextValue::kString;
      v.s = string_literal();
    } else if (c == '-' || c == '+' || c == '.' || (c >= '0' && c <= '9')) {
      number(v);
    } else if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      const std::string id = identifier();
      if (id == "true" || id == "false") v.kind = TextValue::kBool, v.i = id == "true";
      else if (id == "null" || id == "nil") v.kind = TextValue::kNil;
      else if (id == "inf") v.kind = TextValue::kReal, v.d = INFINITY;
      else if (id == "inf_neg") v.kind = TextValue::kReal, v.d = -INFINITY;
      else if (id == "nan") v.kind = TextValue::kReal, v.d = NAN;
      else if (peek() == '[') {
        // A typed container, Array[Dictionary]([…]) or Dictionary[String, Variant]({…}): the
        // type list is skipped, the value kept.
        ++at_;
        while (peek() != ']') {
          value(depth + 1);
          if (peek() == ',') ++at_;
          else if (peek() != ']') fail("expected ',' or ']'");
        }
        ++at_;
        expect('(');
        v = value(depth + 1);
        expect(')');
      } else if (peek() == '(') {
        ++at_;
        v.kind = TextValue::kCall;
        v.s = id;
        if (id == "PackedByteArray") return packed_bytes(v);
        while (peek() != ')') {
          TextValue a = value(depth + 1);
          if (a.number()) v.nums.push_back(a.as_double());
          else v.items.push_back(std::move(a));
          if (peek() == ',') ++at_;
          else if (peek() != ')') fail("expected ',' or ')'");
        }
        ++at_;
      } else {
        fail("unexpected identifier '" + id + "'");
      }
    } else {
      fail(at_ < t_.size() ? "unexpected '" + std::string(1, c) + "'" : "unexpected end of text");
    }
    return v;
  }

  // A property's or header field's name: an identifier with '/', ':', '.' (or a quoted string).
  std::string key() {
    if (peek() == '"') return string_literal();
    std::string k;
    while (at_ < t_.size() && t_[at_] != '=' && t_[at_] != ']' && !std::isspace(static_cast<unsigned char>(t_[at_])))
      k += t_[at_++];
    if (k.empty()) fail("expected a name");
    return k;
  }

 private:
  void skip_space() {
    while (at_ < t_.size()) {
      const char c = t_[at_];
      if (c == ';') {  // a comment to the end of the line
        while (at_ < t_.size() && t_[at_] != '\n') ++at_;
      } else if (std::isspace(static_cast<unsigned char>(c))) {
        ++at_;
      } else {
        break;
      }
    }
  }
  std::string identifier() {
    std::string id;
    while (at_ < t_.size() && (std::isalnum(static_cast<unsigned char>(t_[at_])) || t_[at_] == '_')) id += t_[at_++];
    return id;
  }
  std::string string_literal() {
    ++at_;  // the opening quote
    std::string s;
    while (true) {
      if (at_ >= t_.size()) fail("unterminated string");
      char c = t_[at_++];
      if (c == '"') return s;
      if (c == '\\') {
        if (at_ >= t_.size()) fail("unterminated string");
        c = t_[at_++];
        c = c == 'n' ? '\n' : c == 't' ? '\t' : c == 'r' ? '\r' : c;
      }
      s += c;
    }
  }
  void number(TextValue& v) {
    const size_t start = at_;
    bool real = false;
    if (t_[at_] == '-' || t_[at_] == '+') ++at_;
    while (at_ < t_.size()) {
      const char c = t_[at_];
      if (c >= '0' && c <= '9') ++at_;
      else if (c == '.' || c == 'e' || c == 'E') real = true, ++at_;
      else if ((c == '-' || c == '+') && (t_[at_ - 1] == 'e' || t_[at_ - 1] == 'E')) ++at_;
      else break;
    }
    const char* b = t_.data() + start + (t_[start] == '+');
    const char* e = t_.data() + at_;
    std::from_chars_result r;
    if (real) v.kind = TextValue::kReal, r = std::from_chars(b, e, v.d);
    else v.kind = TextValue::kInt, r = std::from_chars(b, e, v.i);
    if (r.ec != std::errc() || r.ptr != e) fail("malformed number '" + std::string(t_.data() + start, e) + "'");
  }
  // PackedByteArray(1, 2, 3) (resource format 3) or PackedByteArray("base64") (format 4).
  TextValue& packed_bytes(TextValue& v) {
    if (peek() == '"') {
      const std::string b64 = string_literal();
      decode_base64(b64, v.bytes);
    } else {
      while (peek() != ')') {
        TextValue a;
        if (peek() == '-' || !std::isdigit(static_cast<unsigned char>(peek())))
          fail("PackedByteArray: expected a byte");
        number(a);
        if (a.kind != TextValue::kInt || a.i < 0 || a.i > 255) fail("PackedByteArray: value outside 0..255");
        v.bytes.push_back(uint8_t(a.i));
        if (peek() == ',') ++at_;
        else if (peek() != ')') fail("expected ',' or ')'");
      }
    }
    expect(')');
    return v;
  }
  void decode_base64(const std::string& in, std::vector<uint8_t>& out) {
    auto digit = [](char c) -> int {
      if (c >= 'A' && c <= 'Z') return c - 'A';
      if (c >= 'a' && c <= 'z') return c - 'a' + 26;
      if (c >= '0' && c <= '9') return c - '0' + 52;
      if (c == '+') return 62;
      if (c == '/') return 63;
      return -1;
    };
    size_t len = in.size();
    if (len % 4 != 0) fail("PackedByteArray: base64 length not a multiple of 4");
    size_t pad = 0;
    while (pad < 2 && len > pad && in[len - 1 - pad] == '=') ++pad;
    out.reserve(len / 4 * 3);
    uint32_t acc = 0;
    for (size_t i = 0; i < len - pad; ++i) {
      const int d = digit(in[i]);
      if (d < 0) fail("PackedByteArray: not base64");
      acc = acc << 6 | uint32_t(d);
      if (i % 4 == 3)
        out.push_back(uint8_t(acc >> 16)), out.push_back(uint8_t(acc >> 8)), out.push_back(uint8_t(acc)), acc = 0;
    }
    if (pad == 1) out.push_back(uint8_t(acc >> 10)), out.push_back(uint8_t(acc >> 2));
    if (pad == 2) out.push_back(uint8_t(acc >> 4));
  }

  const std::string& t_;
  const std::string& src_;
  size_t at_ = 0;
};

const TextValue* dict_get(const TextValue& d, const char* key) {
  for (size_t k = 0; k + 1 < d.items.size(); k += 2)
    if (d.items[k].kind == TextValue::kString && d.items[k].s == key) return &d.items[k + 1];
  return nullptr;
}

std::vector<Surface> surfaces_of_text(const TextValue& v, const std::string& source) {
  if (v.kind != TextValue::kArray) throw file_error(source, "_surfaces is not an array");
  std::vector<Surface> out;
  for (size_t i = 0; i < v.items.size(); ++i) {
    const TextValue& d = v.items[i];
    const std::string where = "surface " + std::to_string(i) + ": ";
    if (d.kind != TextValue::kDict) fail(source, where, "not a dictionary");
    Surface s;
    auto integer = [&](const char* key, bool* has, auto* to) {
      const TextValue* x = dict_get(d, key);
      if (!x) return;
      if (x->kind != TextValue::kInt) fail(source, where, std::string(key) + " is not an integer");
      *has = true;
      *to = static_cast<std::remove_pointer_t<decltype(to)>>(x->i);
    };
    auto bytes = [&](const char* key, Bytes* to) {
      const TextValue* x = dict_get(d, key);
      if (!x) return;
      if (x->kind != TextValue::kCall || x->s != "PackedByteArray")
        fail(source, where, std::string(key) + " is not a PackedByteArray");
      to->data = x->bytes.data(), to->size = x->bytes.size(), to->present = true;
    };
    integer("format", &s.has_format, &s.format);
    integer("primitive", &s.has_primitive, &s.primitive);
    integer("vertex_count", &s.has_vertex_count, &s.vertex_count);
    integer("index_count", &s.has_index_count, &s.index_count);
    bytes("vertex_data", &s.vertex);
    bytes("attribute_data", &s.attribute);
    bytes("index_data", &s.index);
    if (const TextValue* a = dict_get(d, "aabb")) {
      if (a->kind != TextValue::kCall || a->s != "AABB" || a->nums.size() != 6 || !a->items.empty())
        fail(source, where, "aabb is not AABB(6 numbers)");
      std::copy(a->nums.begin(), a->nums.end(), s.aabb);
      s.has_aabb = true;
    }
    if (const TextValue* u = dict_get(d, "uv_scale")) {
      if (u->kind != TextValue::kCall || u->s != "Vector4" || u->nums.size() != 4 || !u->items.empty())
        fail(source, where, "uv_scale is not Vector4(4 numbers)");
      std::copy(u->nums.begin(), u->nums.end(), s.uv_scale);
    }
    out.push_back(s);
  }
  return out;
}

// The sections of a text resource/scene: headers `[tag field=value …]` and `key = value` lines.
// Calls on_header(tag, fields) and on_property(key, begin, end) with the value's text span.
template <class OnHeader, class OnProperty>
void walk_text_resource(const std::string& text, const std::string& source, OnHeader on_header,
                        OnProperty on_property) {
  TextParser p(text, source);
  while (!p.eof()) {
    if (p.peek() == '[') {
      p.expect('[');
      const std::string tag = p.key();
      std::vector<std::pair<std::string, TextValue>> fields;
      while (p.peek() != ']') {
        std::string k = p.key();
        p.expect('=');
        fields.emplace_back(std::move(k), p.value());
      }
      p.expect(']');
      on_header(tag, fields);
    } else {
      const std::string k = p.key();
      p.expect('=');
      p.peek();
      const size_t begin = p.at();
      p.value();
      on_property(k, begin, p.at());
    }
  }
}

const TextValue* field(const std::vector<std::pair<std::string, TextValue>>& fields, const char* name) {
  for (const auto& f : fields)
    if (f.first == name) return &f.second;
  return nullptr;
}

MeshTriangles mesh_of_binary(const std::string& bytes, const std::string& source) {
  const GodotBinaryResource res =
      parse_godot_binary_resource(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), source);
  if (res.type != "ArrayMesh")
    throw file_error(source, "the resource is a " + res.type + ", not an ArrayMesh");
  const GodotBinaryValue* surfaces = nullptr;
  for (const auto& p : res.properties)
    if (p.first == "_surfaces") surfaces = &p.second;
  if (!surfaces) throw file_error(source, "the ArrayMesh has no _surfaces property");
  if (surfaces->tag != 30) throw file_error(source, "_surfaces is not an array");
  std::vector<Surface> out;
  for (size_t i = 0; i < surfaces->items.size(); ++i) {
    const GodotBinaryValue& d = surfaces->items[i];
    const std::string where = "surface " + std::to_string(i) + ": ";
    if (d.tag != 26) fail(source, where, "not a dictionary");
    Surface s;
    for (size_t k = 0; k + 1 < d.items.size(); k += 2) {
      const std::string& key = d.items[k].text;
      const GodotBinaryValue& v = d.items[k + 1];
      const bool integer = v.tag == 3 || v.tag == 40;
      auto need = [&](bool ok, const char* what) {
        if (!ok) fail(source, where, key + " is not " + what);
      };
      if (d.items[k].tag != 5 && d.items[k].tag != 44) continue;  // keys are strings
      if (key == "format") need(integer, "an integer"), s.format = uint64_t(v.i64), s.has_format = true;
      else if (key == "primitive") need(integer, "an integer"), s.primitive = v.i64, s.has_primitive = true;
      else if (key == "vertex_count") need(integer, "an integer"), s.vertex_count = v.i64, s.has_vertex_count = true;
      else if (key == "index_count") need(integer, "an integer"), s.index_count = v.i64, s.has_index_count = true;
      else if (key == "vertex_data" || key == "attribute_data" || key == "index_data") {
        need(v.tag == 31, "a PackedByteArray");
        Bytes& b = key == "vertex_data" ? s.vertex : key == "attribute_data" ? s.attribute : s.index;
        b.data = v.bytes, b.size = v.byte_count, b.present = true;
      } else if (key == "aabb") {
        need(v.tag == 15, "an AABB");
        std::copy(v.num, v.num + 6, s.aabb);
        s.has_aabb = true;
      } else if (key == "uv_scale") {
        need(v.tag == 50, "a Vector4");
        std::copy(v.num, v.num + 4, s.uv_scale);
      }
    }
    out.push_back(s);
  }
  return decode_surfaces(out, source);
}

}  // namespace

MeshTriangles godot_array_mesh_text(const std::string& surfaces, const std::string& source) {
  TextParser p(surfaces, source);
  const TextValue v = p.value();
  if (!p.eof()) p.fail("text after the _surfaces array");
  return decode_surfaces(surfaces_of_text(v, source), source);
}

MeshTriangles godot_mesh_resource_file(const std::string& bytes, const std::string& source) {
  if (bytes.size() >= 4 && (bytes.compare(0, 4, "RSRC") == 0 || bytes.compare(0, 4, "RSCC") == 0))
    return mesh_of_binary(bytes, source);
  bool first = true, in_main = false;
  std::string type;
  size_t begin = 0, end = 0;
  bool found = false;
  walk_text_resource(
      bytes, source,
      [&](const std::string& tag, const std::vector<std::pair<std::string, TextValue>>& fields) {
        if (first) {
          if (tag != "gd_resource")
            throw file_error(source, "not a Godot text resource (no [gd_resource] header first)");
          const TextValue* t = field(fields, "type");
          type = t && t->kind == TextValue::kString ? t->s : "";
          if (type != "ArrayMesh")
            throw file_error(source, "the resource is a " + type + ", not an ArrayMesh");
        }
        first = false;
        in_main = tag == "resource";
      },
      [&](const std::string& key, size_t b, size_t e) {
        if (first) throw file_error(source, "not a Godot text resource (no [gd_resource] header first)");
        if (in_main && key == "_surfaces") begin = b, end = e, found = true;
      });
  if (first) throw file_error(source, "not a Godot text resource (empty)");
  if (!found) throw file_error(source, "the ArrayMesh has no _surfaces property");
  return godot_array_mesh_text(bytes.substr(begin, end - begin), source);
}

MeshTriangles godot_text_sub_resource_mesh(const std::string& text, const std::string& id, const std::string& source) {
  bool in_it = false, seen = false, found = false;
  size_t begin = 0, end = 0;
  walk_text_resource(
      text, source,
      [&](const std::string& tag, const std::vector<std::pair<std::string, TextValue>>& fields) {
        const TextValue* i = field(fields, "id");
        in_it = tag == "sub_resource" && i && i->kind == TextValue::kString && i->s == id;
        if (in_it) {
          const TextValue* t = field(fields, "type");
          if (!t || t->kind != TextValue::kString || t->s != "ArrayMesh")
            throw file_error(source, "sub_resource " + id + " is not an ArrayMesh");
          seen = true;
        }
      },
      [&](const std::string& key, size_t b, size_t e) {
        if (in_it && key == "_surfaces") begin = b, end = e, found = true;
      });
  if (!seen) throw file_error(source, "no [sub_resource type=\"ArrayMesh\" id=\"" + id + "\"]");
  if (!found) throw file_error(source, "ArrayMesh " + id + " has no _surfaces property");
  return godot_array_mesh_text(text.substr(begin, end - begin), source);
}

}  // namespace ahd
