#include "containers/ktx2.h"

#include <zstd.h>

#include <algorithm>
#include <numeric>

#include "containers/byte_io.h"
#include "containers/limits.h"
#include "core/error.h"
#include "core/large_buffer.h"
#include "codecs/pixel_format_table.h"

namespace ahd {
namespace {

constexpr uint8_t kIdentifier[12] = {0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
constexpr uint32_t kSchemeNone = 0, kSchemeZstd = 2;
constexpr size_t kHeaderBytes = 80, kLevelIndexEntry = 24;
constexpr uint32_t kMaxDimension = 1u << 16;
constexpr uint32_t kMaxLayers = 2048;  // D3D11's array limit, and plenty for lightmap atlas pages

uint32_t type_size(PixelFormat f) { return pixel_format_row(f).ktx2.type_size; }

}  // namespace

std::vector<uint8_t> write_ktx2(const Texture& tex, const Ktx2WriteOptions& opt) {
  using namespace bytes;
  const FormatInfo& fi = format_info(tex.format);
  if (!(pixel_format_row(tex.format).containers & kInKtx2)) throw Error(std::string("KTX2: cannot hold ") + fi.name);
  check_texture_levels(tex, "KTX2", kMaxDimension);
  const uint32_t w = tex.levels[0].width, h = tex.levels[0].height;
  const uint32_t levels = uint32_t(tex.levels.size());

  std::vector<uint8_t> b(kIdentifier, kIdentifier + 12);
  put32(b, fi.vk_format);
  put32(b, type_size(tex.format));
  put32(b, w);
  put32(b, h);
  put32(b, 0);  // pixelDepth: 2D
  put32(b, tex.layers > 1 ? tex.layers : 0);  // layerCount: 0 = not an array
  put32(b, 1);  // faceCount
  put32(b, levels);
  put32(b, opt.zstd ? kSchemeZstd : kSchemeNone);
  const size_t index_at = b.size();
  b.resize(kHeaderBytes + kLevelIndexEntry * levels, 0);  // index + level index, filled below

  // Data Format Descriptor.
  const size_t dfd_at = b.size();
  for (uint32_t word : ktx2_dfd(tex.format)) put32(b, word);
  const size_t dfd_len = b.size() - dfd_at;

  // Key/value data, sorted by key bytes; ours first win over duplicates in tex.metadata.
  std::vector<std::pair<std::string, std::string>> kv = {{"KTXorientation", "rd"},
                                                         {"KTXwriter", "ahdpack " AHD_VERSION_STRING}};
  for (const auto& p : tex.metadata)
    if (std::none_of(kv.begin(), kv.end(), [&](const auto& q) { return q.first == p.first; })) kv.push_back(p);
  std::sort(kv.begin(), kv.end());
  const size_t kvd_at = b.size();
  for (const auto& [k, v] : kv) {
    put32(b, uint32_t(k.size() + 1 + v.size() + 1));
    b.insert(b.end(), k.begin(), k.end());
    b.push_back(0);
    b.insert(b.end(), v.begin(), v.end());
    b.push_back(0);
    pad_to(b, 4);
  }
  const size_t kvd_len = b.size() - kvd_at;

  // Levels, smallest first, each aligned to lcm(block bytes, 4) (1 when supercompressed).
  const size_t align = opt.zstd ? 1 : std::lcm(size_t(fi.bytes_per_block), size_t(4));
  if (!opt.zstd) {
    // The whole file is known in size: one allocation, advised for huge pages, instead of the
    // vector doubling (and faulting in fresh 4 KB pages at each copy) as the levels are appended.
    size_t total = b.size();
    for (const TextureLevel& lv : tex.levels) total += lv.data.size() + align;
    std::vector<uint8_t> whole;
    whole.reserve(total);
    advise_huge_pages(whole.data(), total);
    whole.assign(b.begin(), b.end());
    b.swap(whole);
  }
  for (int l = int(levels) - 1; l >= 0; --l) {
    const std::vector<uint8_t>& raw = tex.levels[size_t(l)].data;
    pad_to(b, align);
    const size_t at = b.size();
    if (opt.zstd) {
      std::vector<uint8_t> z(ZSTD_compressBound(raw.size()));
      const size_t n = ZSTD_compress(z.data(), z.size(), raw.data(), raw.size(), opt.zstd_level);
      if (ZSTD_isError(n)) throw Error(std::string("KTX2: zstd failed: ") + ZSTD_getErrorName(n));
      b.insert(b.end(), z.begin(), z.begin() + std::ptrdiff_t(n));
    } else {
      b.insert(b.end(), raw.begin(), raw.end());
    }
    const size_t e = kHeaderBytes + kLevelIndexEntry * size_t(l);
    set64(b, e, at);
    set64(b, e + 8, b.size() - at);
    set64(b, e + 16, raw.size());
  }
  set32(b, index_at + 0, uint32_t(dfd_at));
  set32(b, index_at + 4, uint32_t(dfd_len));
  set32(b, index_at + 8, uint32_t(kvd_at));
  set32(b, index_at + 12, uint32_t(kvd_len));
  set64(b, index_at + 16, 0);  // no supercompression global data
  set64(b, index_at + 24, 0);
  return b;
}

namespace {

// Inflates one zstd level of `expect` bytes (already validated against the size limit). Streams
// into memory that grows with what the frame really produces, never past `expect`: a tiny frame
// that merely claims a large content size fails after producing what it holds, without the
// full-size buffer ever being allocated and zeroed (the 2 GiB allocation bomb of issue 15).
void inflate_level(const bytes::Reader& r, uint32_t l, const uint8_t* src, size_t len, size_t expect,
                   std::vector<uint8_t>* out) {
  struct DCtx {
    ZSTD_DCtx* p = ZSTD_createDCtx();
    ~DCtx() { ZSTD_freeDCtx(p); }
  } ctx;
  if (!ctx.p) r.fail("level " + std::to_string(l) + ": cannot create a zstd decoder");
  // The window (zstd's own allocation) stays at zstd's default limit of 2^27 bytes.
  ZSTD_DCtx_setParameter(ctx.p, ZSTD_d_windowLogMax, 27);
  ZSTD_inBuffer in{src, len, 0};
  std::vector<uint8_t> chunk(std::min<size_t>(expect, size_t(1) << 17) + 1);
  out->clear();
  for (;;) {
    ZSTD_outBuffer o{chunk.data(), chunk.size(), 0};
    const size_t rc = ZSTD_decompressStream(ctx.p, &o, &in);
    if (ZSTD_isError(rc)) r.fail("level " + std::to_string(l) + ": corrupt zstd data (" + ZSTD_getErrorName(rc) + ")");
    if (out->size() + o.pos > expect) r.fail("level " + std::to_string(l) + ": zstd data inflates past the level size");
    if (out->size() + o.pos > out->capacity())
      out->reserve(std::min(expect, std::max(out->capacity() * 2, out->size() + o.pos)));
    out->insert(out->end(), chunk.data(), chunk.data() + o.pos);
    if (rc == 0) break;  // frame complete
    if (in.pos == in.size && o.pos < o.size) r.fail("level " + std::to_string(l) + ": truncated zstd data");
  }
  if (out->size() != expect) r.fail("level " + std::to_string(l) + ": zstd data holds fewer bytes than the level");
  if (in.pos != in.size) r.fail("level " + std::to_string(l) + ": bytes after the zstd frame");
}

}  // namespace

Texture read_ktx2(const uint8_t* data, size_t size, const std::string& path) {
  bytes::Reader r(data, size, path);
  if (size < kHeaderBytes || !std::equal(kIdentifier, kIdentifier + 12, data)) r.fail("not a KTX2 file (bad identifier)");
  Texture tex;
  const uint32_t vk = r.u32(12), tsize = r.u32(16), w = r.u32(20), h = r.u32(24), depth = r.u32(28),
                 layers = r.u32(32), faces = r.u32(36), levels = r.u32(40), scheme = r.u32(44);
  if (!format_from_vk(vk, &tex.format) || !(pixel_format_row(tex.format).containers & kInKtx2))
    r.fail("unsupported vkFormat " + std::to_string(vk));
  if (tsize != type_size(tex.format)) r.fail("typeSize " + std::to_string(tsize) + " does not match the format");
  if (w == 0 || h == 0 || w > kMaxDimension || h > kMaxDimension)
    r.fail("unsupported size " + std::to_string(w) + "x" + std::to_string(h));
  if (depth != 0 || faces != 1) r.fail("only 2D textures (arrays included) with one face are supported");
  if (layers > kMaxLayers) r.fail("unsupported layer count " + std::to_string(layers));
  tex.layers = std::max(1u, layers);
  check_layered_size(path, w, h, tex.layers);
  if (levels == 0 || levels > full_mip_count(w, h)) r.fail("invalid level count " + std::to_string(levels));
  if (scheme != kSchemeNone && scheme != kSchemeZstd) r.fail("unsupported supercompression scheme " + std::to_string(scheme));
  r.need(kHeaderBytes, uint64_t(kLevelIndexEntry) * levels, "level index");

  // DFD: must describe the format the header names.
  const uint32_t dfd_at = r.u32(48), dfd_len = r.u32(52);
  const std::vector<uint32_t> want = ktx2_dfd(tex.format);
  if (dfd_len < 28) r.fail("missing Data Format Descriptor");
  r.need(dfd_at, dfd_len, "Data Format Descriptor");
  if (r.u32(dfd_at) != dfd_len) r.fail("Data Format Descriptor size mismatch");
  const uint32_t model_word = r.u32(dfd_at + 12), dims = r.u32(dfd_at + 16), planes = r.u32(dfd_at + 20);
  if ((model_word & 0xFF) != (want[3] & 0xFF) || dims != want[4] || (planes & 0xFF) != (want[5] & 0xFF))
    r.fail("Data Format Descriptor does not match vkFormat");
  // The samples too (issue 26: garbage samples were accepted): the same count, and each sample's
  // bit offset, bit length, channel type and position as the format's own descriptor; only the
  // sample bounds (lower/upper) may differ between writers.
  if (dfd_len != want.size() * 4) r.fail("Data Format Descriptor has the wrong number of samples for vkFormat");
  for (size_t w7 = 7; w7 + 1 < want.size(); w7 += 4)
    if (r.u32(dfd_at + 4 * w7) != want[w7] || r.u32(dfd_at + 4 * (w7 + 1)) != want[w7 + 1])
      r.fail("Data Format Descriptor sample " + std::to_string((w7 - 7) / 4) + " does not match vkFormat");

  // Key/value data.
  const uint32_t kvd_at = r.u32(56), kvd_len = r.u32(60);
  r.need(kvd_at, kvd_len, "key/value data");
  for (uint64_t p = kvd_at; p + 4 <= uint64_t(kvd_at) + kvd_len;) {
    const uint32_t n = r.u32(p);
    if (n == 0 || n > uint64_t(kvd_at) + kvd_len - (p + 4)) r.fail("malformed key/value entry");
    const uint8_t* e = r.at(p + 4, n, "key/value entry");
    const uint8_t* nul = std::find(e, e + n, uint8_t(0));
    if (nul == e + n) r.fail("key without NUL terminator");
    std::string key(e, nul), value(nul + 1, e + n);
    if (!value.empty() && value.back() == '\0') value.pop_back();
    tex.metadata.emplace_back(std::move(key), std::move(value));
    p += 4 + n;
    p = (p + 3) & ~uint64_t(3);
  }

  // Levels: after the header, level index, DFD and key/value data, and not overlapping each other
  // (issue 26: levels inside the header and overlapping levels were accepted).
  const uint64_t data_start = std::max({uint64_t(kHeaderBytes) + uint64_t(kLevelIndexEntry) * levels,
                                        uint64_t(dfd_at) + dfd_len, uint64_t(kvd_at) + kvd_len});
  std::vector<std::pair<uint64_t, uint64_t>> spans;
  for (uint32_t l = 0; l < levels; ++l) {
    const uint64_t e = kHeaderBytes + kLevelIndexEntry * uint64_t(l);
    const uint64_t off = r.u64(e), len = r.u64(e + 8);
    if (off < data_start) r.fail("level " + std::to_string(l) + " data lies inside the header or metadata");
    spans.emplace_back(off, len);
  }
  std::sort(spans.begin(), spans.end());
  for (size_t i = 1; i < spans.size(); ++i)
    if (spans[i].first - spans[i - 1].first < spans[i - 1].second) r.fail("level data ranges overlap");
  tex.levels.resize(levels);
  for (uint32_t l = 0; l < levels; ++l) {
    const uint64_t e = kHeaderBytes + kLevelIndexEntry * uint64_t(l);
    const uint64_t off = r.u64(e), len = r.u64(e + 8), ulen = r.u64(e + 16);
    TextureLevel& lv = tex.levels[l];
    lv.width = std::max(1u, w >> l);
    lv.height = std::max(1u, h >> l);
    const size_t expect = size_t(tex.layers) * level_size_bytes(tex.format, lv.width, lv.height);
    if (ulen != expect) r.fail("level " + std::to_string(l) + " has " + std::to_string(ulen) + " bytes, expected " + std::to_string(expect));
    const uint8_t* src = r.at(off, len, "level data");
    if (scheme == kSchemeNone) {
      if (len != expect) r.fail("level " + std::to_string(l) + " byte length mismatch");
      lv.data.assign(src, src + len);
    } else {
      const unsigned long long content = ZSTD_getFrameContentSize(src, len);
      if (content != expect) r.fail("level " + std::to_string(l) + ": zstd frame size does not match the level");
      inflate_level(r, l, src, size_t(len), expect, &lv.data);
    }
  }
  return tex;
}

}  // namespace ahd
