#include "image/exr_read.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfChromaticitiesAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfInputPart.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfThreading.h>
#include <OpenEXR/ImfTileDescription.h>

#include <Imath/half.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstring>
#include <mutex>
#include <thread>

#include "containers/limits.h"
#include "core/error.h"
#include "core/parallel.h"
#include "image/exr_zip.h"

namespace ahd {

bool is_exr_bytes(const std::vector<uint8_t>& b) {
  return b.size() >= 4 && b[0] == 0x76 && b[1] == 0x2f && b[2] == 0x31 && b[3] == 0x01;
}

namespace {

// The file's bytes as an OpenEXR stream; memory-mapped, so OpenEXR reads chunks without copies.
class MemStream : public Imf::IStream {
 public:
  MemStream(const std::string& path, const std::vector<uint8_t>& b)
      : Imf::IStream(path.c_str()), data_(reinterpret_cast<const char*>(b.data())), size_(b.size()) {}
  bool isMemoryMapped() const override { return true; }
  char* readMemoryMapped(int n) override {
    if (n < 0 || uint64_t(n) > size_ - pos_) throw Iex::InputExc("unexpected end of file");
    char* p = const_cast<char*>(data_ + pos_);
    pos_ += uint64_t(n);
    return p;
  }
  bool read(char c[], int n) override {
    if (n < 0 || uint64_t(n) > size_ - pos_) throw Iex::InputExc("unexpected end of file");
    std::memcpy(c, data_ + pos_, size_t(n));
    pos_ += uint64_t(n);
    return pos_ < size_;
  }
  uint64_t tellg() override { return pos_; }
  void seekg(uint64_t pos) override { pos_ = std::min<uint64_t>(pos, size_); }
  void clear() override {}

 private:
  const char* data_;
  uint64_t size_;
  uint64_t pos_ = 0;
};

// OpenImageIO's names of OpenEXR's codecs (the "compression" attribute), for max_expansion.
const char* codec_name(Imf::Compression c) {
  switch (c) {
    case Imf::NO_COMPRESSION:
      return "none";
    case Imf::RLE_COMPRESSION:
      return "rle";
    case Imf::ZIPS_COMPRESSION:
      return "zips";
    case Imf::ZIP_COMPRESSION:
      return "zip";
    case Imf::PIZ_COMPRESSION:
      return "piz";
    case Imf::PXR24_COMPRESSION:
      return "pxr24";
    case Imf::B44_COMPRESSION:
      return "b44";
    case Imf::B44A_COMPRESSION:
      return "b44a";
    case Imf::DWAA_COMPRESSION:
      return "dwaa";
    case Imf::DWAB_COMPRESSION:
      return "dwab";
    default:
      return "unknown";
  }
}

// OpenImageIO's channel order, so callers see the names where they saw them before: by layer (the
// name up to its last '.'), within a layer the known suffixes first (R, G, B, Y, A, Z, …, case
// ignored) in this order, then the rest by name.
int special_rank(const std::string& suffix) {
  static const char* kSpecial[] = {"R",     "Red", "G",  "Green", "B",  "Blue", "Y",  "real", "imag",  "A",
                                   "Alpha", "AR",  "RA", "AG",    "GA", "AB",   "BA", "Z",    "Depth", "Zback"};
  for (int i = 0; i < int(sizeof kSpecial / sizeof *kSpecial); ++i) {
    const char* s = kSpecial[i];
    if (suffix.size() == std::strlen(s) &&
        std::equal(suffix.begin(), suffix.end(), s, [](char a, char b) { return std::tolower(a) == std::tolower(b); }))
      return i;
  }
  return 10000;
}

struct ChannelKey {
  std::string name, layer, suffix;
  int rank;
};

std::vector<std::string> ordered_channels(const Imf::ChannelList& list) {
  std::vector<ChannelKey> keys;
  for (auto it = list.begin(); it != list.end(); ++it) {
    ChannelKey k;
    k.name = it.name();
    const size_t dot = k.name.find_last_of('.');
    k.layer = dot == std::string::npos ? std::string() : k.name.substr(0, dot + 1);
    k.suffix = dot == std::string::npos ? k.name : k.name.substr(dot + 1);
    k.rank = special_rank(k.suffix);
    keys.push_back(std::move(k));
  }
  std::stable_sort(keys.begin(), keys.end(), [](const ChannelKey& a, const ChannelKey& b) {
    if (a.layer != b.layer) return a.layer < b.layer;
    if (a.rank != b.rank) return a.rank < b.rank;
    return a.suffix < b.suffix;
  });
  std::vector<std::string> names;
  for (auto& k : keys) names.push_back(std::move(k.name));
  return names;
}

// OpenEXR's decoding pool of up to 4 threads, started by the first file big enough to gain from it
// (chunks decode independently: the values never depend on the count). Process-wide.
void start_openexr_pool() {
  static std::once_flag once;
  std::call_once(once, [] {
    const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
    Imf::setGlobalThreadCount(int(std::min(hw, 4u)));
  });
  // OpenEXR's own header bound (Header::setMaxImageSize) is left unset, as OpenImageIO left it:
  // it is process-wide, so it would also refuse OpenImageIO's writes and replace our
  // check_declared_image message; our check runs before any pixel buffer is sized.
}

// Below this many bytes of pixels for OpenEXR to decode, a file is decoded on the calling thread:
// handing its few chunks to pool threads (and starting them) cost more than it saved. Plain 256²
// (0.4 MB as half): 6 % less CPU and 8 % less wall time; plain 1024² (6 MB) keeps the pool, which
// shortens its wall time (docs/performance-real.md "Small maps, round 9"). ZIP parts do not count:
// read_zip_rows decodes them on ahd's own pool.
constexpr double kPoolFromBytes = 2.0 * 1024 * 1024;

// Every channel half or float and sampled at every texel: what this reader decodes (handles()).
bool flat_half_or_float(const Imf::Header& h) {
  for (auto it = h.channels().begin(); it != h.channels().end(); ++it) {
    const Imf::Channel& c = it.channel();
    if (c.xSampling != 1 || c.ySampling != 1) return false;
    if (c.type != Imf::HALF && c.type != Imf::FLOAT) return false;
  }
  return true;
}

// Whether read_rows decodes `h`'s chunks itself (image/exr_zip.h): ZIP or ZIPS scanlines of
// flat_half_or_float channels, on a little-endian machine (the chunks' byte order).
bool zip_part(const Imf::Header& h) {
  if (!exr_zip_available() || h.hasTileDescription() || (h.hasType() && h.type() != Imf::SCANLINEIMAGE)) return false;
  if (h.compression() != Imf::ZIP_COMPRESSION && h.compression() != Imf::ZIPS_COMPRESSION) return false;
  const uint16_t one = 1;
  uint8_t low = 0;
  std::memcpy(&low, &one, 1);
  return low == 1 && flat_half_or_float(h);
}

// The decoded size of the pixels OpenEXR would decode (the parts zip_part leaves to it), as the
// headers declare them.
double declared_pixel_bytes(const Imf::MultiPartInputFile& f) {
  double bytes = 0;
  for (int p = 0; p < f.parts(); ++p) {
    const Imf::Header& h = f.header(p);
    if (zip_part(h)) continue;
    const Imath::Box2i dw = h.dataWindow();
    const double area = (double(dw.max.x) - dw.min.x + 1) * (double(dw.max.y) - dw.min.y + 1);
    for (auto it = h.channels().begin(); it != h.channels().end(); ++it)
      bytes += area * (it.channel().type == Imf::HALF ? 2 : 4) /
               (double(std::max(1, it.channel().xSampling)) * std::max(1, it.channel().ySampling));
  }
  return bytes;
}

std::string first_line(const char* what) {
  std::string s = what;
  return s.substr(0, s.find('\n'));
}

}  // namespace

struct ExrReader::Impl {
  std::string path;
  uint64_t file_bytes = 0;
  MemStream stream;
  std::unique_ptr<Imf::MultiPartInputFile> file;
  std::vector<std::unique_ptr<Imf::InputPart>> parts;
  Impl(const std::string& p, const std::vector<uint8_t>& b, uint64_t n) : path(p), file_bytes(n), stream(p, b) {}

  const Imf::Header& header(int part) const {
    if (part < 0 || part >= file->parts())
      throw file_error(path,
                       "no part " + std::to_string(part) + " (the file has " + std::to_string(file->parts()) + ")");
    return file->header(part);
  }
};

ExrReader::ExrReader(const std::string& path, const std::vector<uint8_t>& bytes)
    : ExrReader(path, bytes, bytes.size()) {}

ExrReader::ExrReader(const std::string& path, const std::vector<uint8_t>& bytes, uint64_t file_bytes)
    : impl_(std::make_unique<Impl>(path, bytes, file_bytes)) {
  try {
    impl_->file = std::make_unique<Imf::MultiPartInputFile>(impl_->stream, Imf::globalThreadCount());
    if (Imf::globalThreadCount() == 0 && declared_pixel_bytes(*impl_->file) >= kPoolFromBytes) {
      // The first big file: the pool starts, and the file is opened again to use it (its header
      // parsed twice, from memory).
      start_openexr_pool();
      impl_->stream.seekg(0);
      impl_->file = std::make_unique<Imf::MultiPartInputFile>(impl_->stream, Imf::globalThreadCount());
    }
  } catch (const std::bad_alloc&) {
    throw file_error(path, "out of memory reading the header");
  } catch (const std::exception& e) {
    throw file_error(path, "cannot read image (" + first_line(e.what()) + ")");
  }
  impl_->parts.resize(size_t(impl_->file->parts()));
}

ExrReader::~ExrReader() = default;

std::vector<std::string> ExrReader::part_names() const {
  std::vector<std::string> names;
  for (int p = 0; p < impl_->file->parts(); ++p) {
    const Imf::Header& h = impl_->file->header(p);
    names.push_back(h.hasName() ? h.name() : std::string());
  }
  return names;
}

bool ExrReader::handles(int part) const {
  const Imf::Header& h = impl_->header(part);
  if (h.hasType() && Imf::isDeepData(h.type())) return true;  // info() refuses it with OIIO's words
  return flat_half_or_float(h);
}

ImageFileInfo ExrReader::info(int part) const {
  const Imf::Header& h = impl_->header(part);
  const std::string& path = impl_->path;
  if (h.hasType() && Imf::isDeepData(h.type()))
    throw file_error(path, "a deep (multi-sample per texel) image: lightmaps are flat images");
  const Imath::Box2i dw = h.dataWindow();
  const int64_t w = int64_t(dw.max.x) - dw.min.x + 1, ht = int64_t(dw.max.y) - dw.min.y + 1;
  int nch = 0;
  for (auto it = h.channels().begin(); it != h.channels().end(); ++it) ++nch;
  if (w <= 0 || ht <= 0 || nch <= 0)
    throw file_error(path, "empty or inverted data window (" + std::to_string(w) + "x" + std::to_string(ht) + ", " +
                               std::to_string(nch) + " channels)");
  if (nch > 64) throw file_error(path, std::to_string(nch) + " channels (at most 64 are read)");
  uint64_t texel_bytes = 0;
  ImageFileInfo info;
  info.is_float = true;
  for (auto it = h.channels().begin(); it != h.channels().end(); ++it) {
    texel_bytes += it.channel().type == Imf::HALF ? 2 : 4;
    if (it.channel().type != Imf::HALF && it.channel().type != Imf::FLOAT) info.is_float = false;
  }
  check_declared_image(path, uint64_t(w), uint64_t(ht), 1, texel_bytes, impl_->file_bytes, codec_name(h.compression()));
  info.width = int(w);
  info.height = int(ht);
  info.channel_names = ordered_channels(h.channels());
  if (const auto* cs = h.findTypedAttribute<Imf::StringAttribute>("oiio:ColorSpace")) info.color_space = cs->value();
  else info.color_space = "Linear";
  if (const auto* c = h.findTypedAttribute<Imf::ChromaticitiesAttribute>("chromaticities")) {
    const Imf::Chromaticities& v = c->value();
    info.chromaticities = {v.red.x, v.red.y, v.green.x, v.green.y, v.blue.x, v.blue.y, v.white.x, v.white.y};
  }
  info.parts = part_names();
  return info;
}

int ExrReader::band_rows(int part) const {
  const Imf::Header& h = impl_->header(part);
  return h.hasTileDescription() ? int(std::min<unsigned>(h.tileDescription().ySize, 1u << 20)) : 64;
}

namespace {

// Rows y0..y1−1 of a zip_part part decoded here, chunk by chunk on the thread pool, into dst as
// read_rows lays them out. False when a chunk is not what OpenEXR would decode without complaint
// (a chunk table or stream it refuses, a stream of another length): read_rows then asks OpenEXR
// for the whole band, so every value and every error is OpenEXR's.
bool read_zip_rows(Imf::InputPart& in, const Imf::Header& h, const std::vector<std::string>& names, int y0, int y1,
                   float* dst) {
  const Imath::Box2i dw = h.dataWindow();
  const size_t w = size_t(int64_t(dw.max.x) - dw.min.x + 1), nch = names.size();
  const int lines = h.compression() == Imf::ZIPS_COMPRESSION ? 1 : 16;
  // The channels in the file's order (the chunk's): their type and their place in a dst texel.
  struct Slot {
    bool half;
    size_t at;
  };
  std::vector<Slot> slots;
  size_t line_bytes = 0;
  for (auto it = h.channels().begin(); it != h.channels().end(); ++it) {
    const bool half = it.channel().type == Imf::HALF;
    const size_t at = size_t(std::find(names.begin(), names.end(), std::string(it.name())) - names.begin());
    if (at >= nch) return false;
    slots.push_back({half, at});
    line_bytes += w * (half ? 2 : 4);
  }
  const int height = dw.max.y - dw.min.y + 1;
  const int c0 = y0 / lines, c1 = (y1 - 1) / lines;
  struct Chunk {
    const uint8_t* raw = nullptr;
    size_t n = 0;
  };
  std::vector<Chunk> chunks(size_t(c1 - c0 + 1));
  try {
    for (int c = c0; c <= c1; ++c) {
      const char* raw = nullptr;
      int n = 0;
      in.rawPixelData(dw.min.y + c * lines, raw, n);  // the stream is memory-mapped: a pointer into the file's bytes
      if (!raw || n <= 0) return false;
      chunks[size_t(c - c0)] = {reinterpret_cast<const uint8_t*>(raw), size_t(n)};
    }
  } catch (const std::exception&) {
    return false;
  }
  std::atomic<bool> failed{false};
  parallel_for(chunks.size(), 0, 1, [&](size_t k) {
    if (failed.load(std::memory_order_relaxed)) return;
    const int c = c0 + int(k);
    const int first = c * lines, count = std::min(lines, height - first);
    thread_local std::vector<uint8_t> bytes;
    const size_t size = line_bytes * size_t(count);
    if (bytes.size() < size) bytes.resize(size);
    if (!exr_unzip_chunk(chunks[k].raw, chunks[k].n, bytes.data(), size)) {
      failed.store(true, std::memory_order_relaxed);
      return;
    }
    // Each line: every channel's w values in turn, little-endian, as OpenEXR converts them to float.
    const uint8_t* src = bytes.data();
    for (int l = 0; l < count; ++l) {
      const int y = first + l;
      const bool wanted = y >= y0 && y < y1;
      float* row = dst + size_t(y - y0) * w * nch;
      for (const Slot& s : slots) {
        if (!wanted) {
          src += w * (s.half ? 2 : 4);
          continue;
        }
        float* o = row + s.at;
        if (s.half) {
          for (size_t x = 0; x < w; ++x, src += 2, o += nch) {
            Imath::half v;
            v.setBits(uint16_t(src[0] | src[1] << 8));
            *o = float(v);
          }
        } else {
          for (size_t x = 0; x < w; ++x, src += 4, o += nch) std::memcpy(o, src, 4);
        }
      }
    }
  });
  return !failed.load();
}

}  // namespace

void ExrReader::read_rows(int part, int y0, int y1, float* dst) {
  const Imf::Header& h = impl_->header(part);
  const std::string& path = impl_->path;
  const Imath::Box2i dw = h.dataWindow();
  const std::vector<std::string> names = ordered_channels(h.channels());
  const size_t nch = names.size();
  const size_t w = size_t(int64_t(dw.max.x) - dw.min.x + 1);
  try {
    auto& in = impl_->parts[size_t(part)];
    if (!in) in = std::make_unique<Imf::InputPart>(*impl_->file, part);
    if (zip_part(h) && read_zip_rows(*in, h, names, y0, y1, dst)) return;
    // The band's own window: its first texel is dst[0] (no pointer before the buffer is formed).
    Imath::Box2i band(Imath::V2i(dw.min.x, dw.min.y + y0), Imath::V2i(dw.max.x, dw.min.y + y1 - 1));
    Imf::FrameBuffer fb;
    for (size_t c = 0; c < nch; ++c)
      fb.insert(names[c], Imf::Slice::Make(Imf::FLOAT, dst + c, band, sizeof(float) * nch, sizeof(float) * nch * w));
    in->setFrameBuffer(fb);
    in->readPixels(dw.min.y + y0, dw.min.y + y1 - 1);
  } catch (const std::bad_alloc&) {
    throw file_error(path, "out of memory reading the pixels");
  } catch (const std::exception& e) {
    throw file_error(path, "cannot read pixels (" + first_line(e.what()) + ")");
  }
}

}  // namespace ahd
