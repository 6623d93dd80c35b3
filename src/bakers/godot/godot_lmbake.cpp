#include "bakers/godot/godot_lmbake.h"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>

#include "core/error.h"
#include "files/input_file.h"

namespace ahd {

namespace {

// The binary format's own variant tags (not Variant::Type; resource_format_binary.cpp).
enum Tag : uint32_t {
  kNil = 1, kBool = 2, kInt = 3, kFloat = 4, kString = 5, kVector2 = 10, kRect2 = 11, kVector3 = 12,
  kPlane = 13, kQuaternion = 14, kAabb = 15, kBasis = 16, kTransform3D = 17, kTransform2D = 18,
  kColor = 20, kNodePath = 22, kRid = 23, kObject = 24, kDictionary = 26, kArray = 30,
  kPackedByte = 31, kPackedInt32 = 32, kPackedFloat32 = 33, kPackedString = 34, kPackedVector3 = 35,
  kPackedColor = 36, kPackedVector2 = 37, kInt64 = 40, kDouble = 41, kStringName = 44, kVector2i = 45,
  kRect2i = 46, kVector3i = 47, kPackedInt64 = 48, kPackedFloat64 = 49, kVector4 = 50, kVector4i = 51,
  kProjection = 52, kPackedVector4 = 53, kCallable = 42, kSignal = 43,
};

// What the readers need of a value (GodotBinaryValue, godot_lmbake.h); everything else is skipped
// (read and bounds-checked, not kept).
using Value = GodotBinaryValue;

class Reader {
 public:
  Reader(const uint8_t* d, size_t n, const std::string& src) : d_(d), n_(n), src_(src) {}
  size_t left() const { return n_ - at_; }
  size_t at() const { return at_; }
  void seek(uint64_t off) {
    if (off > n_) fail("offset " + std::to_string(off) + " beyond the end");
    at_ = size_t(off);
  }
  const uint8_t* take(size_t k) {
    if (k > left()) fail("truncated at byte " + std::to_string(at_));
    const uint8_t* p = d_ + at_;
    at_ += k;
    return p;
  }
  uint32_t u32() {
    const uint8_t* p = take(4);
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
  }
  uint16_t u16() {
    const uint8_t* p = take(2);
    return uint16_t(p[0] | p[1] << 8);
  }
  uint64_t u64() {
    const uint64_t lo = u32();
    return lo | uint64_t(u32()) << 32;
  }
  float f32() {
    const uint32_t b = u32();
    float f;
    std::memcpy(&f, &b, 4);
    return f;
  }
  double f64() {
    const uint64_t b = u64();
    double f;
    std::memcpy(&f, &b, 8);
    return f;
  }
  // A length-prefixed UTF-8 string (the length counts a trailing NUL, which is dropped).
  std::string str() {
    const uint32_t len = u32();
    const uint8_t* p = take(len);
    std::string s(reinterpret_cast<const char*>(p), len);
    while (!s.empty() && s.back() == '\0') s.pop_back();
    return s;
  }
  // A count of items of at least `min_bytes` each: refused when the bytes left cannot hold them.
  uint32_t count(uint32_t raw, size_t min_bytes) {
    if (min_bytes && raw > left() / min_bytes) fail("count " + std::to_string(raw) + " exceeds the file");
    return raw;
  }
  [[noreturn]] void fail(const std::string& why) const { throw file_error(src_, "not a readable Godot resource (" + why + ")"); }

 private:
  const uint8_t* d_;
  size_t n_, at_ = 0;
  const std::string& src_;
};

struct Parser {
  Reader& r;
  std::vector<std::string> strings;
  bool real64 = false;
  // Bytes copied out of the string table: a 4-byte reference can name a long string, and a
  // NodePath of 65 535 such references per user asked for 13 GB from 462 KB. Bounded by the file.
  uint64_t copied = 0, budget = 0;

  // A string by its table index, or inline when the top bit is set (_get_string).
  std::string name() {
    const uint32_t id = r.u32();
    if (id & 0x80000000u) {
      const uint32_t len = id & 0x7fffffffu;
      const uint8_t* p = r.take(len);
      std::string s(reinterpret_cast<const char*>(p), len);
      while (!s.empty() && s.back() == '\0') s.pop_back();
      return s;
    }
    if (id >= strings.size()) r.fail("string index " + std::to_string(id) + " outside the table");
    copied += strings[id].size() + 1;
    if (copied > budget)
      r.fail("its string references copy more than " + std::to_string(budget) + " bytes (16 × the file + 1 MiB)");
    return strings[id];
  }

  void skip_reals(size_t k) { r.take(k * (real64 ? 8 : 4)); }
  double real() { return real64 ? r.f64() : double(r.f32()); }

  Value value(int depth) {
    if (depth > 32) r.fail("values nested deeper than 32");
    Value v;
    v.tag = r.u32();
    const size_t rs = real64 ? 8 : 4;
    switch (v.tag) {
      case kNil: case kCallable: case kSignal: break;  // no payload (Callable and Signal are not saved)
      case kBool: case kInt: v.i64 = int32_t(r.u32()), v.num[0] = double(v.i64); break;
      case kInt64: v.i64 = int64_t(r.u64()), v.num[0] = double(v.i64); break;
      case kFloat: v.num[0] = r.f32(); break;
      case kDouble: v.num[0] = r.f64(); break;
      case kString: case kStringName: v.text = r.str(); break;
      case kRect2: case kVector4: for (int k = 0; k < 4; ++k) v.num[k] = real(); break;
      case kAabb: for (double& x : v.num) x = real(); break;
      case kVector2: skip_reals(2); break;
      case kVector3: skip_reals(3); break;
      case kPlane: case kQuaternion: skip_reals(4); break;
      case kTransform2D: skip_reals(6); break;
      case kBasis: skip_reals(9); break;
      case kTransform3D: skip_reals(12); break;
      case kProjection: skip_reals(16); break;
      case kColor: r.take(16); break;
      case kVector2i: r.take(8); break;
      case kVector3i: r.take(12); break;
      case kRect2i: case kVector4i: r.take(16); break;
      case kRid: r.take(4); break;
      case kNodePath: {
        const uint32_t names = r.u16();
        uint32_t subnames = r.u16();
        const bool absolute = subnames & 0x8000u;
        subnames &= 0x7fffu;
        if (absolute) v.text = "/";
        for (uint32_t i = 0; i < names; ++i) v.text += (i ? "/" : "") + name();
        for (uint32_t i = 0; i < subnames; ++i) v.text += ":" + name();
        break;
      }
      case kObject: {
        const uint32_t kind = r.u32();
        if (kind == 1) r.str(), r.str();     // external resource by type and path
        else if (kind == 2 || kind == 3) r.u32();  // internal / external by index
        else if (kind != 0) r.fail("object reference of kind " + std::to_string(kind));
        break;
      }
      case kDictionary: {
        const uint32_t n = r.count(r.u32() & 0x7fffffffu, 8);
        v.items.reserve(size_t(n) * 2);
        for (uint32_t i = 0; i < 2 * n; ++i) v.items.push_back(value(depth + 1));
        break;
      }
      case kArray: {
        const uint32_t n = r.count(r.u32() & 0x7fffffffu, 4);
        v.items.reserve(n);
        for (uint32_t i = 0; i < n; ++i) v.items.push_back(value(depth + 1));
        break;
      }
      case kPackedByte: {
        const uint32_t n = r.count(r.u32(), 1);
        v.bytes = r.take(n), v.byte_count = n;
        r.take((4 - n % 4) % 4);  // padded to 4 bytes
        break;
      }
      case kPackedInt32: case kPackedFloat32: r.take(size_t(r.count(r.u32(), 4)) * 4); break;
      case kPackedInt64: case kPackedFloat64: r.take(size_t(r.count(r.u32(), 8)) * 8); break;
      case kPackedVector2: r.take(size_t(r.count(r.u32(), 2 * rs)) * 2 * rs); break;
      case kPackedVector3: r.take(size_t(r.count(r.u32(), 3 * rs)) * 3 * rs); break;
      case kPackedVector4: r.take(size_t(r.count(r.u32(), 4 * rs)) * 4 * rs); break;
      case kPackedColor: r.take(size_t(r.count(r.u32(), 16)) * 16); break;
      case kPackedString: {
        const uint32_t n = r.count(r.u32(), 4);
        for (uint32_t i = 0; i < n; ++i) r.str();
        break;
      }
      default: r.fail("value of unknown tag " + std::to_string(v.tag) + " at byte " + std::to_string(r.at() - 4));
    }
    return v;
  }
};

bool is_int(const Value& v) { return v.tag == kInt || v.tag == kInt64; }

}  // namespace

GodotLightmapData parse_godot_lmbake(const uint8_t* data, size_t size, const std::string& source) {
  Reader r(data, size, source);
  if (size >= 4 && std::memcmp(data, "RSCC", 4) == 0)
    throw file_error(source, "a compressed Godot resource (RSCC) is not read: save it uncompressed from Godot's editor");
  if (size < 4 || std::memcmp(data, "RSRC", 4) != 0)
    throw file_error(source, "not a Godot binary resource (no RSRC header; a text .tres is not read)");
  r.take(4);
  if (r.u32() != 0) throw file_error(source, "big-endian Godot resource: not read");
  const bool real64_header = r.u32() != 0;
  GodotLightmapData out;
  out.engine_major = int(r.u32());
  out.engine_minor = int(r.u32());
  out.format = int(r.u32());
  // Format 3: Godot 3.x NodePath encoding; 4: string ids of sub-resources (4.0, 4.1); 5: a script
  // class in the header (4.2); 6: the PackedVector4Array tag (4.3 and later). The header and the
  // values read here are laid out alike in all four (resource_format_binary.cpp, FORMAT_VERSION).
  if (out.format < 3 || out.format > 6)
    throw file_error(source, "Godot resource format " + std::to_string(out.format) + " (written by Godot " +
                                 std::to_string(out.engine_major) + "." + std::to_string(out.engine_minor) +
                                 ") is not read: formats 3..6 are (Godot 3.x to 4.x)");
  out.type = r.str();
  r.u64();  // import metadata offset
  const uint32_t flags = r.u32();
  Parser p{r, {}, real64_header || (flags & 4u)};
  p.budget = 16 * uint64_t(size) + (uint64_t(1) << 20);
  r.u64();                           // uid: always stored, meaningful when flags has FORMAT_FLAG_UIDS (2)
  if (flags & 8u) r.str();           // script class
  r.take(11 * 4);                    // reserved fields
  const uint32_t nstrings = r.count(r.u32(), 4);
  p.strings.reserve(nstrings);
  for (uint32_t i = 0; i < nstrings; ++i) p.strings.push_back(r.str());
  const uint32_t next = r.count(r.u32(), 8);
  for (uint32_t i = 0; i < next; ++i) {
    r.str();  // type
    out.external.push_back(r.str());
    if (flags & 2u) r.u64();
  }
  const uint32_t nint = r.count(r.u32(), 12);
  if (nint == 0) throw file_error(source, "Godot resource holds no resource");
  uint64_t main_offset = 0;
  for (uint32_t i = 0; i < nint; ++i) {
    r.str();  // path ("local://…")
    main_offset = r.u64();  // the main resource is the last one
  }
  r.seek(main_offset);
  const std::string type = r.str();
  if (!type.empty()) out.type = type;
  const uint32_t nprops = r.count(r.u32(), 8);
  for (uint32_t i = 0; i < nprops; ++i) {
    const std::string key = p.name();
    const Value v = p.value(0);
    if (key == "uses_spherical_harmonics") out.uses_spherical_harmonics = v.num[0] != 0;
    if (key == "_uses_packed_directional") out.has_packed_directional = true, out.packed_directional = v.num[0] != 0;
    if (key != "user_data") continue;
    if (v.tag != kArray || v.items.size() % 4 != 0)
      throw file_error(source, "user_data is not an array of (path, rectangle, slice, sub-instance) tuples");
    for (size_t k = 0; k < v.items.size(); k += 4) {
      const Value* t = &v.items[k];
      if (t[0].tag != kNodePath || t[1].tag != kRect2 || !is_int(t[2]) || !is_int(t[3]))
        throw file_error(source, "user_data entry " + std::to_string(k / 4) + " is not (NodePath, Rect2, int, int)");
      GodotLightmapUser u;
      u.path = t[0].text;
      for (int c = 0; c < 4; ++c) u.rect[c] = t[1].num[c];
      // Range-checked as int64 before the cast (a 64-bit slice of 2^40 made the cast undefined).
      if (t[2].i64 < 0 || t[2].i64 > 2047)
        throw file_error(source, "user '" + u.path + "' has slice " + std::to_string(t[2].i64));
      if (t[3].i64 < INT32_MIN || t[3].i64 > INT32_MAX)
        throw file_error(source, "user '" + u.path + "' has sub-instance " + std::to_string(t[3].i64));
      u.slice = int(t[2].i64);
      u.sub_instance = int(t[3].i64);
      out.users.push_back(u);
    }
  }
  return out;
}

GodotBinaryResource parse_godot_binary_resource(const uint8_t* data, size_t size, const std::string& source) {
  Reader r(data, size, source);
  if (size >= 4 && std::memcmp(data, "RSCC", 4) == 0)
    throw file_error(source, "compressed Godot binary resource (RSCC): not read");
  if (size < 4 || std::memcmp(data, "RSRC", 4) != 0)
    throw file_error(source, "not a Godot binary resource (no RSRC header)");
  r.take(4);
  if (r.u32() != 0) throw file_error(source, "big-endian Godot resource: not read");
  const bool real64_header = r.u32() != 0;
  GodotBinaryResource out;
  out.engine_major = int(r.u32());
  out.engine_minor = int(r.u32());
  out.format = int(r.u32());
  // Format 6 (Godot 4.3+) only adds the PackedVector4Array tag, which value() reads.
  if (out.format < 3 || out.format > 6)
    throw file_error(source, "Godot resource format " + std::to_string(out.format) + " is not read (3..6)");
  out.type = r.str();
  r.u64();  // import metadata offset
  // Flags, the uid and 11 reserved words: 14 words in every format (Godot 3 writes them all as
  // reserved zeros; Godot 4 writes the uid field whether or not the UID flag is set).
  const uint32_t flags = r.u32();
  Parser p{r, {}, real64_header || (flags & 4u)};
  p.budget = 16 * uint64_t(size) + (uint64_t(1) << 20);
  r.u64();                  // uid
  if (flags & 8u) r.str();  // script class
  r.take(11 * 4);           // reserved fields
  const uint32_t nstrings = r.count(r.u32(), 4);
  p.strings.reserve(nstrings);
  for (uint32_t i = 0; i < nstrings; ++i) p.strings.push_back(r.str());
  const uint32_t next = r.count(r.u32(), 8);
  for (uint32_t i = 0; i < next; ++i) {
    r.str(), r.str();  // type, path
    if (flags & 2u) r.u64();
  }
  const uint32_t nint = r.count(r.u32(), 12);
  if (nint == 0) throw file_error(source, "Godot resource holds no resource");
  uint64_t main_offset = 0;
  for (uint32_t i = 0; i < nint; ++i) {
    r.str();                // path ("local://…")
    main_offset = r.u64();  // the main resource is the last one
  }
  r.seek(main_offset);
  const std::string type = r.str();
  if (!type.empty()) out.type = type;
  const uint32_t nprops = r.count(r.u32(), 8);
  out.properties.reserve(nprops);
  for (uint32_t i = 0; i < nprops; ++i) {
    std::string key = p.name();
    out.properties.emplace_back(std::move(key), p.value(0));
  }
  return out;
}

GodotLightmapData read_godot_lmbake(const std::string& path) {
  const std::vector<uint8_t> bytes = read_input_bytes(path, InputKind::kLmbake);
  return parse_godot_lmbake(bytes.data(), bytes.size(), path);
}

}  // namespace ahd
