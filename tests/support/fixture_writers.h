// Writers of small input files for the bad-input and reader tests: a one-triangle glTF, Godot's
// binary resource format.
#pragma once
#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace ahd_test {

// Standard base64 (RFC 4648, padded) of `d`: data: URIs and embedded files.
inline std::string base64(const std::vector<uint8_t>& d) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string s;
  for (size_t i = 0; i < d.size(); i += 3) {
    const uint32_t n = uint32_t(d[i]) << 16 | (i + 1 < d.size() ? uint32_t(d[i + 1]) << 8 : 0) | (i + 2 < d.size() ? d[i + 2] : 0);
    s += t[n >> 18 & 63];
    s += t[n >> 12 & 63];
    s += i + 1 < d.size() ? t[n >> 6 & 63] : '=';
    s += i + 2 < d.size() ? t[n & 63] : '=';
  }
  return s;
}

// A glTF of one triangle (3 vertices, POSITION + TEXCOORD_0, and TEXCOORD_1 the same UVs when
// `uv2`; indices `idx` as uint16) in a data: URI; `nodes_json` replaces the node list, `extra` is
// added to the buffer's byteLength.
inline std::string gltf_triangle(const std::array<uint16_t, 3>& idx, const std::string& nodes_json = "[{\"mesh\": 0}]",
                                 int extra = 0, bool uv2 = false) {
  std::vector<uint8_t> buf;
  auto f32 = [&](float v) {
    uint8_t b[4];
    std::memcpy(b, &v, 4);
    buf.insert(buf.end(), b, b + 4);
  };
  for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) f32(v);  // 36 bytes positions
  for (float v : {0.f, 0.f, 1.f, 0.f, 0.f, 1.f}) f32(v);                 // 24 bytes UVs
  for (uint16_t i : idx) buf.push_back(uint8_t(i)), buf.push_back(uint8_t(i >> 8));
  buf.push_back(0), buf.push_back(0);  // pad to 4
  const std::string enc = base64(buf);
  return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": )" + nodes_json +
         R"(, "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1)" + std::string(uv2 ? ", \"TEXCOORD_1\": 1" : "") +
         R"(}, "indices": 2}]}],
  "buffers": [{"byteLength": )" + std::to_string(buf.size() + size_t(extra)) +
         R"(, "uri": "data:application/octet-stream;base64,)" + enc + R"("}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 24},
                  {"buffer": 0, "byteOffset": 60, "byteLength": 6}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0,0,0], "max": [1,1,0]},
                {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"},
                {"bufferView": 2, "componentType": 5123, "count": 3, "type": "SCALAR"}]})";
}

// A little-endian writer of Godot's binary resource (RSRC) format.
struct Rsrc {
  std::vector<uint8_t> b;
  void u32(uint32_t v) {
    for (int i = 0; i < 4; ++i) b.push_back(uint8_t(v >> (8 * i)));
  }
  void u16(uint16_t v) { b.push_back(uint8_t(v)), b.push_back(uint8_t(v >> 8)); }
  void u64(uint64_t v) { u32(uint32_t(v)), u32(uint32_t(v >> 32)); }
  void f32(float f) {
    uint32_t w;
    std::memcpy(&w, &f, 4);
    u32(w);
  }
  void str(const std::string& s) {  // length counts a trailing NUL
    u32(uint32_t(s.size() + 1));
    b.insert(b.end(), s.begin(), s.end());
    b.push_back(0);
  }
  // After the header: the string table, no external and one internal resource (local://TYPE_1)
  // whose offset points just past the table, and that resource's type; its property count and
  // properties come next.
  void one_resource(const std::vector<std::string>& strings, const std::string& type) {
    u32(uint32_t(strings.size()));
    for (const std::string& s : strings) str(s);
    u32(0);  // external resources
    u32(1);  // internal resources
    str("local://" + type + "_1");
    const size_t offset_at = b.size();
    u64(0);
    const uint64_t main = b.size();
    for (int i = 0; i < 8; ++i) b[offset_at + size_t(i)] = uint8_t(main >> (8 * i));
    str(type);
  }
};

}  // namespace ahd_test
