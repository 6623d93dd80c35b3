#include "io/image_io.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include <unistd.h>

#include "containers/limits.h"
#include "io/image_file.h"
#include "core/error.h"
#include "io/input_record.h"
#include "io/output_set.h"

namespace ahd {
namespace fs = std::filesystem;

OpenedImage open_image_file(const std::string& path, const OIIO::ImageSpec* config) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw file_error(path, "file not found");
  OpenedImage f;
  f.path = path;
  f.bytes = read_file_bytes(path);
  f.proxy = std::make_unique<OIIO::Filesystem::IOMemReader>(f.bytes.data(), f.bytes.size());
  f.in = OIIO::ImageInput::open(path, config, f.proxy.get());
  if (!f.in) {
    std::string why = OIIO::geterror();
    if (why.empty()) why = "not a readable image";
    // OIIO messages can span lines; keep the first.
    why = why.substr(0, why.find('\n'));
    throw file_error(path, "cannot read image (" + why + ")");
  }
  return f;
}

void check_image_spec(const OpenedImage& f, const OIIO::ImageSpec& spec, uint64_t layers) {
  if (spec.deep) throw file_error(f.path, "a deep (multi-sample per texel) image: lightmaps are flat images");
  if (spec.depth > 1) throw file_error(f.path, "volume images are not supported");
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    throw file_error(f.path, "empty or inverted data window (" + std::to_string(spec.width) + "x" +
                                 std::to_string(spec.height) + ", " + std::to_string(spec.nchannels) + " channels)");
  if (spec.nchannels > 64) throw file_error(f.path, std::to_string(spec.nchannels) + " channels (at most 64 are read)");
  check_declared_image(f.path, uint64_t(spec.width), uint64_t(spec.height), layers, spec.pixel_bytes(true),
                       f.bytes.size(), spec.get_string_attribute("compression", f.in->format_name()));
}

namespace {

// The memory proxy keeps one snapshot of the file for both the header and the pixels.
OpenedImage open_input(const std::string& path) {
  // Alpha in lightmap data is a number of its own (Unity's rebalancing factor), not opacity: keep
  // the stored colours instead of OIIO's default of multiplying them by alpha.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  return open_image_file(path, &config);
}

}  // namespace

std::string temp_path_for(const std::string& path) {
  static thread_local std::mt19937_64 rng{std::random_device{}()};
  fs::path p(path);
  // ".<name>.ahdtmp-<pid>-<random><ext>": hidden, recognisable (remove_stale_temporaries in
  // io/output_set.h removes those whose process is gone), and ending in the final extension so
  // OpenImageIO picks the right writer.
  char tag[48];
  std::snprintf(tag, sizeof tag, ".ahdtmp-%ld-%08x", long(::getpid()), unsigned(rng()));
  return (p.parent_path() / ("." + p.filename().string() + tag + p.extension().string())).string();
}



namespace {

// Every part's name; OpenEXR multi-part files name their parts, other files have one unnamed part.
std::vector<std::string> part_names(OIIO::ImageInput& in) {
  std::vector<std::string> names;
  for (int p = 0; in.seek_subimage(p, 0); ++p) names.push_back(in.spec().get_string_attribute("oiio:subimagename"));
  return names;
}

// Positions `in` on `part`, or throws naming how many parts the file has.
void seek_part(OIIO::ImageInput& in, const std::string& path, int part, size_t part_count) {
  if (part < 0 || size_t(part) >= part_count || !in.seek_subimage(part, 0))
    throw file_error(path, "no part " + std::to_string(part) + " (the file has " + std::to_string(part_count) + ")");
}

}  // namespace

namespace {

// The header of `part` of an opened file, checked (check_image_spec) before anything is sized by it.
ImageFileInfo info_of(OpenedImage& f, int part) {
  ImageFileInfo info;
  info.parts = part_names(*f.in);
  seek_part(*f.in, f.path, part, info.parts.size());
  const OIIO::ImageSpec& spec = f.in->spec();
  // Refuse at the header, before any pixel is read or the pipeline runs (a 100000x1 EXR used to be
  // fitted for 18 s and then refused by the container writer without a file name; a 13.9 KB EXR
  // claiming 11000² L2 texels asked for 13 GB).
  check_image_spec(f, spec);
  info.width = spec.width;
  info.height = spec.height;
  info.channel_names = spec.channelnames;
  info.is_float = true;
  for (int c = 0; c < spec.nchannels; ++c) {
    OIIO::TypeDesc t = spec.channelformat(c);
    if (t.basetype != OIIO::TypeDesc::HALF && t.basetype != OIIO::TypeDesc::FLOAT &&
        t.basetype != OIIO::TypeDesc::DOUBLE)
      info.is_float = false;
  }
  // RGBE .hdr files are float data stored in 8-bit mantissas; OIIO reports them as float.
  info.color_space = spec.get_string_attribute("oiio:ColorSpace");
  if (const OIIO::ParamValue* c = spec.find_attribute("chromaticities"))
    if (c->type().basetype == OIIO::TypeDesc::FLOAT && c->type().size() == 8 * sizeof(float)) {
      const float* v = static_cast<const float*>(c->data());
      info.chromaticities.assign(v, v + 8);
    }
  return info;
}

}  // namespace

ImageFileInfo read_image_info(const std::string& path, int part) {
  OpenedImage f = open_input(path);
  return info_of(f, part);
}

ImageF read_image(const std::string& path, ImageFileInfo* info_out, int part) {
  OpenedImage f = open_input(path);
  const ImageFileInfo info = info_of(f, part);  // leaves f.in on `part`
  if (info_out) *info_out = info;
  const OIIO::ImageSpec spec = f.in->spec();
  try {
    ImageF img(spec.width, spec.height, spec.nchannels);
    if (!f.in->read_image(part, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, img.data.data())) {
      std::string why = f.in->geterror();
      throw file_error(path, "cannot read pixels (" + why.substr(0, why.find('\n')) + ")");
    }
    return img;
  } catch (const std::bad_alloc&) {
    throw file_error(path, "out of memory reading the pixels");
  }
}

void read_image_rows(const std::string& path, int part, ImageFileInfo* info_out,
                     const std::function<void(int y0, int y1, const float* rows)>& fn,
                     const std::function<void(const ImageFileInfo&)>& on_header) {
  OpenedImage f = open_input(path);
  const ImageFileInfo info = info_of(f, part);
  if (info_out) *info_out = info;
  if (on_header) on_header(info);
  const OIIO::ImageSpec spec = f.in->spec();
  auto& in = f.in;
  const int band = spec.tile_height > 0 ? spec.tile_height : 64;
  const size_t row = size_t(spec.width) * spec.nchannels;
  std::vector<float> buf(row * size_t(std::min(band, spec.height)));
  for (int y0 = 0; y0 < spec.height; y0 += band) {
    const int y1 = std::min(spec.height, y0 + band);
    const bool ok = spec.tile_width > 0
                        ? in->read_tiles(part, 0, spec.x, spec.x + spec.width, spec.y + y0, spec.y + y1, spec.z,
                                         spec.z + 1, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, buf.data())
                        : in->read_scanlines(part, 0, spec.y + y0, spec.y + y1, spec.z, 0, spec.nchannels,
                                             OIIO::TypeDesc::FLOAT, buf.data());
    if (!ok) {
      std::string why = in->geterror();
      throw file_error(path, "cannot read pixels (" + why.substr(0, why.find('\n')) + ")");
    }
    fn(y0, y1, buf.data());
  }
}

std::vector<uint8_t> encode_image(const std::string& path, const ImageF& img, bool half_float,
                                  const std::vector<std::string>& channel_names) {
  std::string ext = fs::path(path).extension().string();
  for (auto& ch : ext) ch = char(std::tolower(ch));
  OIIO::TypeDesc fmt = OIIO::TypeDesc::FLOAT;
  if (ext == ".exr") fmt = half_float ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT;
  else if (ext == ".png" || ext == ".tga") fmt = OIIO::TypeDesc::UINT8;
  OIIO::ImageSpec spec(img.width, img.height, img.channels, fmt);
  if (!channel_names.empty()) {
    if (int(channel_names.size()) != img.channels) throw Error("write_image: channel name count mismatch");
    spec.channelnames = channel_names;
  } else if (img.channels == 1) {
    spec.channelnames = {"Y"};
  }
  if (ext == ".exr") spec.attribute("compression", "zip");
  spec.attribute("oiio:UnassociatedAlpha", 1);  // store the numbers as given (see open_input)
  auto out = OIIO::ImageOutput::create(path);
  if (!out) throw file_error(path, "no image writer for this extension");
  std::vector<uint8_t> bytes;
  auto fail = [&](std::unique_ptr<OIIO::ImageOutput>& o) {
    std::string why = o->geterror();
    throw file_error(path, "cannot write image (" + why.substr(0, why.find('\n')) + ")");
  };
  if (out->supports("ioproxy")) {  // EXR, PNG, …: straight into memory
    OIIO::Filesystem::IOVecOutput proxy(bytes);
    if (!out->set_ioproxy(&proxy) || !out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, img.data.data()) ||
        !out->close())
      fail(out);
    return bytes;
  }
  // A writer without I/O proxies (OIIO 2.4: TGA, HDR): a private temporary file in the system's
  // temporary folder, its writer's errors checked, read back whole and removed.
  const std::string tmp = temp_path_for((fs::temp_directory_path() / fs::path(path).filename()).string());
  const bool ok = out->open(tmp, spec) && out->write_image(OIIO::TypeDesc::FLOAT, img.data.data()) && out->close();
  if (!ok) {
    std::error_code ec;
    fs::remove(tmp, ec);
    fail(out);
  }
  out.reset();
  try {
    bytes = read_file_bytes(tmp);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
  std::error_code ec;
  fs::remove(tmp, ec);
  return bytes;
}

void write_image(const std::string& path, const ImageF& img, bool half_float,
                 const std::vector<std::string>& channel_names) {
  publish_file(path, encode_image(path, img, half_float, channel_names));
}

void write_file_atomic(const std::string& path, std::vector<uint8_t> bytes) { publish_file(path, std::move(bytes)); }

void write_file_atomic(const std::string& path, const std::string& text) {
  publish_file(path, std::vector<uint8_t>(text.begin(), text.end()));
}

std::vector<uint8_t> read_file_bytes(const std::string& path, size_t max_bytes) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw file_error(path, "file not found");
  // A device or pipe (/dev/zero) has no size to bound the read by: refused, not read forever.
  if (!fs::is_regular_file(path, ec)) throw file_error(path, "not a regular file");
  const auto size = fs::file_size(path, ec);
  if (ec) throw file_error(path, "cannot read size (" + ec.message() + ")");
  if (size > max_bytes)
    throw file_error(path, "file too large (" + std::to_string(size) + " bytes, at most " + std::to_string(max_bytes) + " are read)");
  std::ifstream f(path, std::ios::binary);
  if (!f) throw file_error(path, "cannot open");
  note_input_file(path);
  std::vector<uint8_t> bytes(size);
  f.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(size));
  if (!f) throw file_error(path, "read failed");
  return bytes;
}

}  // namespace ahd

namespace ahd {

std::string read_text_file(const std::string& path, size_t max_bytes) {
  const std::vector<uint8_t> b = read_file_bytes(path, max_bytes);
  return std::string(b.begin(), b.end());
}

}  // namespace ahd
