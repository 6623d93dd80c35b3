#include "image/image_io.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>


#include "containers/limits.h"
#include "image/exr_read.h"
#include "image/image_file.h"
#include "image/texture_image.h"
#include "core/error.h"
#include "files/input_record.h"
#include "files/file_io.h"
#include "files/input_file.h"
#include "files/output_set.h"
#include "files/utf8_path.h"

namespace ahd {
namespace fs = std::filesystem;

namespace {

std::vector<uint8_t> read_image_bytes(const std::string& path) {
  // A symlink loop is "symbolic links loop", not "file not found" (input_exists).
  if (!input_exists(path)) throw file_error(path, "file not found");
  return read_file_bytes(path);
}

}  // namespace

OpenedImage::OpenedImage(OpenedImage&& o) noexcept
    : path(std::move(o.path)), bytes(std::move(o.bytes)), oiio(o.oiio), handle(o.handle), spec(std::move(o.spec)) {
  o.handle = nullptr;
}

OpenedImage::~OpenedImage() {
  if (handle) oiio->close(handle);
}

bool OpenedImage::seek(int part, int mip) { return oiio->seek(handle, part, mip, &spec); }

OpenedImage open_image_bytes(const std::string& path, std::vector<uint8_t> bytes, bool unassociated_alpha) {
  OpenedImage f;
  f.path = path;
  f.bytes = std::move(bytes);
  f.oiio = &oiio_module(path);
  std::string why;
  // The bytes do not move after this: the handle reads them in place.
  f.handle = f.oiio->open(path, f.bytes.data(), f.bytes.size(), unassociated_alpha, &why);
  if (!f.handle) {
    if (why.empty()) why = "not a readable image";
    throw file_error(path, "cannot read image (" + why + ")");
  }
  if (!f.seek(0, 0)) throw file_error(path, "cannot read image (no image in the file)");
  return f;
}

OpenedImage open_image_file(const std::string& path, bool unassociated_alpha) {
  return open_image_bytes(path, read_image_bytes(path), unassociated_alpha);
}

void check_image_spec(const OpenedImage& f, const OiioSpec& spec, uint64_t layers) {
  if (spec.deep) throw file_error(f.path, "a deep (multi-sample per texel) image: lightmaps are flat images");
  if (spec.depth > 1) throw file_error(f.path, "volume images are not supported");
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    throw file_error(f.path, "empty or inverted data window (" + std::to_string(spec.width) + "x" +
                                 std::to_string(spec.height) + ", " + std::to_string(spec.nchannels) + " channels)");
  if (spec.nchannels > 64) throw file_error(f.path, std::to_string(spec.nchannels) + " channels (at most 64 are read)");
  check_declared_image(f.path, uint64_t(spec.width), uint64_t(spec.height), layers, spec.pixel_bytes, f.bytes.size(),
                       spec.codec);
}

namespace {

// The memory proxy keeps one snapshot of the file for both the header and the pixels.
OpenedImage open_input(const std::string& path, std::vector<uint8_t> bytes) {
  // Alpha in lightmap data is a number of its own (Unity's rebalancing factor), not opacity: keep
  // the stored colours instead of OIIO's default of multiplying them by alpha.
  return open_image_bytes(path, std::move(bytes), true);
}

// An EXR part of half and float channels goes to OpenEXR directly (exr_read.h); anything else
// (other formats, integer EXR channels) to OpenImageIO. Null: not ours.
std::unique_ptr<ExrReader> exr_reader_for(const std::string& path, const std::vector<uint8_t>& bytes, int part) {
  if (!is_exr_bytes(bytes)) return nullptr;
  auto r = std::make_unique<ExrReader>(path, bytes);
  if (!r->handles(part)) return nullptr;
  return r;
}

}  // namespace




namespace {

// Every part's name; OpenEXR multi-part files name their parts, other files have one unnamed part.
std::vector<std::string> part_names(OpenedImage& f) {
  std::vector<std::string> names;
  for (int p = 0; f.seek(p, 0); ++p) names.push_back(f.spec.part_name);
  return names;
}

// Positions `f` on `part`, or throws naming how many parts the file has.
void seek_part(OpenedImage& f, int part, size_t part_count) {
  if (part < 0 || size_t(part) >= part_count || !f.seek(part, 0))
    throw file_error(f.path, "no part " + std::to_string(part) + " (the file has " + std::to_string(part_count) + ")");
}

}  // namespace

namespace {

// The header of `part` of an opened file, checked (check_image_spec) before anything is sized by it.
ImageFileInfo info_of(OpenedImage& f, int part) {
  ImageFileInfo info;
  info.parts = part_names(f);
  seek_part(f, part, info.parts.size());
  const OiioSpec& spec = f.spec;
  // Refuse at the header, before any pixel is read or the pipeline runs (a 100000x1 EXR used to be
  // fitted for 18 s and then refused by the container writer without a file name; a 13.9 KB EXR
  // claiming 11000² L2 texels asked for 13 GB).
  check_image_spec(f, spec);
  info.width = spec.width;
  info.height = spec.height;
  info.channel_names = spec.channel_names;
  // RGBE .hdr files are float data stored in 8-bit mantissas; OIIO reports them as float.
  info.is_float = spec.is_float;
  info.color_space = spec.color_space;
  info.chromaticities = spec.chromaticities;
  return info;
}

}  // namespace

struct ImageInfoScope::Memo {
  struct Entry {
    std::string path;
    int part;
    ImageFileInfo info;
  };
  std::vector<Entry> entries;  // a conversion reads a few files: a linear scan is fine
};

namespace {
thread_local ImageInfoScope::Memo* current_memo = nullptr;

ImageFileInfo read_image_info_uncached(const std::string& path, int part);
}  // namespace

ImageInfoScope::ImageInfoScope() : previous_(current_memo), memo_(new Memo) { current_memo = memo_; }

ImageInfoScope::~ImageInfoScope() {
  current_memo = previous_;
  delete memo_;
}

ImageFileInfo read_image_info(const std::string& path, int part) {
  ImageInfoScope::Memo* m = current_memo;
  if (!m) return read_image_info_uncached(path, part);
  for (const ImageInfoScope::Memo::Entry& e : m->entries)
    if (e.part == part && e.path == path) {
      if (!input_exists(path)) throw file_error(path, "file not found");
      note_input_file(path);
      return e.info;
    }
  ImageFileInfo info = read_image_info_uncached(path, part);
  m->entries.push_back({path, part, info});
  return info;
}

namespace {

ImageFileInfo read_image_info_uncached(const std::string& path, int part) {
  // An EXR's headers (and chunk tables) are at its start: the first 256 KB answer for any lightmap
  // seen, where the whole file is read several times per conversion otherwise (the layout's
  // detection, the batch's schedule: 113 MB each for a 1024² L2 canonical EXR). Anything the head
  // does not answer (a header past it, a part OpenImageIO reads, an error) is asked of the whole
  // file below, so the result and every error are the whole file's.
  if (!input_exists(path)) throw file_error(path, "file not found");
  uint64_t file_bytes = 0;
  const std::vector<uint8_t> head = read_input_head(path, input_file_bound(InputKind::kImage), size_t(256) << 10, &file_bytes);
  if (head.size() < file_bytes && is_exr_bytes(head)) {
    try {
      ExrReader exr(path, head, file_bytes);
      if (exr.handles(part)) return exr.info(part);
    } catch (const std::exception&) {
      // the whole file's answer below
    }
  }
  std::vector<uint8_t> bytes = head.size() == file_bytes ? head : read_image_bytes(path);
  if (auto exr = exr_reader_for(path, bytes, part)) return exr->info(part);
  if (is_texture_container_bytes(bytes)) return read_texture_info(path, bytes, part);  // KTX2 / DDS: texture_image.h
  OpenedImage f = open_input(path, std::move(bytes));
  return info_of(f, part);
}

}  // namespace

ImageF read_image(const std::string& path, ImageFileInfo* info_out, int part) {
  std::vector<uint8_t> bytes = read_image_bytes(path);
  if (is_texture_container_bytes(bytes)) return read_texture_image(path, bytes, part, info_out);
  if (auto exr = exr_reader_for(path, bytes, part)) {
    const ImageFileInfo info = exr->info(part);
    if (info_out) *info_out = info;
    try {
      ImageF img(info.width, info.height, int(info.channel_names.size()));
      exr->read_rows(part, 0, info.height, img.data.data());
      return img;
    } catch (const std::bad_alloc&) {
      throw file_error(path, "out of memory reading the pixels");
    }
  }
  OpenedImage f = open_input(path, std::move(bytes));
  const ImageFileInfo info = info_of(f, part);  // leaves f.in on `part`
  if (info_out) *info_out = info;
  const OiioSpec spec = f.spec;
  try {
    ImageF img(spec.width, spec.height, spec.nchannels);
    std::string why;
    if (!f.oiio->read_image(f.handle, part, 0, img.data.data(), &why))
      throw file_error(path, "cannot read pixels (" + why + ")");
    return img;
  } catch (const std::bad_alloc&) {
    throw file_error(path, "out of memory reading the pixels");
  }
}

namespace {

// `height` rows of `row` floats each, `band` rows at a time through `read_band(y0, y1, buf)` into
// one reused buffer, each band handed to `fn`: the file is never held decoded whole.
template <class ReadBand>
void for_each_band(int height, size_t row, int band, const ReadBand& read_band,
                   const std::function<void(int y0, int y1, const float* rows)>& fn) {
  std::vector<float> buf(row * size_t(std::min(band, height)));
  for (int y0 = 0; y0 < height; y0 += band) {
    const int y1 = std::min(height, y0 + band);
    read_band(y0, y1, buf.data());
    fn(y0, y1, buf.data());
  }
}

}  // namespace

void read_image_rows(const std::string& path, int part, ImageFileInfo* info_out,
                     const std::function<void(int y0, int y1, const float* rows)>& fn,
                     const std::function<void(const ImageFileInfo&)>& on_header) {
  std::vector<uint8_t> bytes = read_image_bytes(path);
  if (auto exr = exr_reader_for(path, bytes, part)) {
    const ImageFileInfo info = exr->info(part);
    if (info_out) *info_out = info;
    if (on_header) on_header(info);
    for_each_band(info.height, size_t(info.width) * info.channel_names.size(), exr->band_rows(part),
                  [&](int y0, int y1, float* buf) { exr->read_rows(part, y0, y1, buf); }, fn);
    return;
  }
  if (is_texture_container_bytes(bytes)) {  // decoded whole (a texture's blocks are not banded by rows)
    ImageFileInfo info;
    const ImageF img = read_texture_image(path, bytes, part, &info);
    if (info_out) *info_out = info;
    if (on_header) on_header(info);
    if (img.height > 0) fn(0, img.height, img.data.data());
    return;
  }
  OpenedImage f = open_input(path, std::move(bytes));
  const ImageFileInfo info = info_of(f, part);
  if (info_out) *info_out = info;
  if (on_header) on_header(info);
  const OiioSpec spec = f.spec;
  for_each_band(spec.height, size_t(spec.width) * size_t(spec.nchannels), spec.tile_height > 0 ? spec.tile_height : 64,
                [&](int y0, int y1, float* buf) {
                  std::string why;
                  if (!f.oiio->read_rows(f.handle, part, y0, y1, buf, &why))
                    throw file_error(path, "cannot read pixels (" + why + ")");
                },
                fn);
}

std::vector<uint8_t> encode_image(const std::string& path, const ImageF& img, bool half_float,
                                  const std::vector<std::string>& channel_names) {
  std::string ext = utf8_string(fs_path(path).extension());
  for (auto& ch : ext) ch = char(std::tolower(ch));
  OiioEncodeLevel l;
  l.width = img.width, l.height = img.height, l.channels = img.channels, l.px = img.data.data();
  if (ext == ".exr") l.format = half_float ? 1 : 0;
  else if (ext == ".png" || ext == ".tga") l.format = 2;
  if (!channel_names.empty()) {
    if (int(channel_names.size()) != img.channels) throw Error("write_image: channel name count mismatch");
    l.channel_names = channel_names;
  } else if (img.channels == 1) {
    l.channel_names = {"Y"};
  }
  if (ext == ".exr") l.string_attrs.push_back({"compression", "zip"});
  l.int_attrs.push_back({"oiio:UnassociatedAlpha", 1});  // store the numbers as given (see open_input)
  // A writer without I/O proxies (OIIO 2.4: TGA, HDR) writes a private temporary file in the
  // system's temporary folder, read back whole and removed by the module.
  const std::string tmp = temp_path_for(utf8_string(fs::temp_directory_path() / fs_path(path).filename()));
  std::vector<uint8_t> bytes;
  std::string why;
  if (!oiio_module(path).encode(path, tmp, {l}, &bytes, &why)) {
    if (why == "no image writer for this extension") throw file_error(path, why);
    throw file_error(path, "cannot write image (" + why + ")");
  }
  return bytes;
}

void write_image(const std::string& path, const ImageF& img, bool half_float,
                 const std::vector<std::string>& channel_names) {
  publish_file(path, encode_image(path, img, half_float, channel_names));
}

}  // namespace ahd
