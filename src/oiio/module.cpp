// libahd_oiio.so: OpenImageIO's calls for ahdpack, loaded with dlopen only when a file needs them
// (src/image/oiio_module.h). Plain calls, no ahdpack state: the checks stay in the process.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <fstream>
#include <memory>

#include "image/oiio_module.h"

namespace {

using ahd::OiioEncodeLevel;
using ahd::OiioSpec;

struct Handle {
  std::unique_ptr<OIIO::Filesystem::IOMemReader> proxy;
  std::unique_ptr<OIIO::ImageInput> in;
};

std::string first_line(std::string s) { return s.substr(0, s.find('\n')); }

void* open_image(const std::string& path, const uint8_t* bytes, size_t size, bool unassociated, std::string* err) {
  try {
    auto h = std::make_unique<Handle>();
    h->proxy = std::make_unique<OIIO::Filesystem::IOMemReader>(const_cast<uint8_t*>(bytes), size);
    OIIO::ImageSpec config;
    if (unassociated) config.attribute("oiio:UnassociatedAlpha", 1);
    h->in = OIIO::ImageInput::open(path, &config, h->proxy.get());
    if (!h->in) {
      *err = first_line(OIIO::geterror());
      return nullptr;
    }
    return h.release();
  } catch (const std::exception& e) {
    *err = first_line(e.what());
    return nullptr;
  }
}

void close_image(void* h) { delete static_cast<Handle*>(h); }

bool seek(void* hv, int part, int mip, OiioSpec* out) {
  auto* h = static_cast<Handle*>(hv);
  if (part < 0 || mip < 0 || !h->in->seek_subimage(part, mip)) return false;
  const OIIO::ImageSpec& s = h->in->spec();
  OiioSpec o;
  o.width = s.width, o.height = s.height, o.nchannels = s.nchannels, o.x = s.x, o.y = s.y, o.z = s.z;
  o.depth = s.depth, o.tile_width = s.tile_width, o.tile_height = s.tile_height, o.deep = s.deep;
  o.pixel_bytes = s.pixel_bytes(true);
  o.codec = s.get_string_attribute("compression", h->in->format_name());
  o.channel_names = s.channelnames;
  o.is_float = true;
  for (int c = 0; c < s.nchannels; ++c) {
    const OIIO::TypeDesc t = s.channelformat(c);
    if (t.basetype != OIIO::TypeDesc::HALF && t.basetype != OIIO::TypeDesc::FLOAT &&
        t.basetype != OIIO::TypeDesc::DOUBLE)
      o.is_float = false;
  }
  o.color_space = s.get_string_attribute("oiio:ColorSpace");
  if (const OIIO::ParamValue* c = s.find_attribute("chromaticities"))
    if (c->type().basetype == OIIO::TypeDesc::FLOAT && c->type().size() == 8 * sizeof(float)) {
      const float* v = static_cast<const float*>(c->data());
      o.chromaticities.assign(v, v + 8);
    }
  o.part_name = s.get_string_attribute("oiio:subimagename");
  *out = std::move(o);
  return true;
}

std::string string_attr(void* h, const std::string& name, const std::string& fallback) {
  return static_cast<Handle*>(h)->in->spec().get_string_attribute(name, fallback);
}

int int_attr(void* h, const std::string& name, int fallback) {
  return static_cast<Handle*>(h)->in->spec().get_int_attribute(name, fallback);
}

bool read_image(void* hv, int part, int mip, float* dst, std::string* err) {
  auto* h = static_cast<Handle*>(hv);
  const int n = h->in->spec().nchannels;
  if (h->in->read_image(part, mip, 0, n, OIIO::TypeDesc::FLOAT, dst)) return true;
  *err = first_line(h->in->geterror());
  return false;
}

bool read_rows(void* hv, int part, int y0, int y1, float* dst, std::string* err) {
  auto& in = static_cast<Handle*>(hv)->in;
  const OIIO::ImageSpec& s = in->spec();
  const bool ok = s.tile_width > 0 ? in->read_tiles(part, 0, s.x, s.x + s.width, s.y + y0, s.y + y1, s.z, s.z + 1, 0,
                                                    s.nchannels, OIIO::TypeDesc::FLOAT, dst)
                                   : in->read_scanlines(part, 0, s.y + y0, s.y + y1, s.z, 0, s.nchannels,
                                                        OIIO::TypeDesc::FLOAT, dst);
  if (!ok) *err = first_line(in->geterror());
  return ok;
}

OIIO::ImageSpec spec_of(const OiioEncodeLevel& l, bool mips) {
  const OIIO::TypeDesc fmt = l.format == 1   ? OIIO::TypeDesc::HALF
                             : l.format == 2 ? OIIO::TypeDesc::UINT8
                                             : OIIO::TypeDesc::FLOAT;
  OIIO::ImageSpec spec(l.width, l.height, l.channels, fmt);
  if (!l.channel_names.empty()) spec.channelnames = l.channel_names;
  if (l.tile > 0) spec.tile_width = spec.tile_height = l.tile;
  if (mips) {  // OpenEXR needs to know up front that the file holds mip levels
    spec.attribute("textureformat", "Plain Texture");
    spec.attribute("openexr:levelmode", 1);  // MIPMAP_LEVELS
  }
  for (const auto& a : l.string_attrs) spec.attribute(a.first, a.second);
  for (const auto& a : l.int_attrs) spec.attribute(a.first, a.second);
  return spec;
}

bool write_levels(OIIO::ImageOutput& out, const std::string& name, const std::vector<OiioEncodeLevel>& levels,
                  std::string* err) {
  const bool mips = levels.size() > 1;
  if (mips && !out.supports("mipmap")) {
    *err = "the writer lacks mip levels";
    return false;
  }
  for (size_t l = 0; l < levels.size(); ++l) {
    const auto mode = l == 0 ? OIIO::ImageOutput::Create : OIIO::ImageOutput::AppendMIPLevel;
    if (!out.open(name, spec_of(levels[l], mips), mode) || !out.write_image(OIIO::TypeDesc::FLOAT, levels[l].px)) {
      *err = first_line(out.geterror());
      return false;
    }
  }
  if (!out.close()) {
    *err = first_line(out.geterror());
    return false;
  }
  return true;
}

bool encode(const std::string& path, const std::string& temp_path, const std::vector<OiioEncodeLevel>& levels,
            std::vector<uint8_t>* bytes, std::string* err) {
  try {
    auto out = OIIO::ImageOutput::create(path);
    if (!out) {
      *err = "no image writer for this extension";
      return false;
    }
    if (out->supports("ioproxy")) {  // EXR, PNG, …: straight into memory
      OIIO::Filesystem::IOVecOutput proxy(*bytes);
      if (!out->set_ioproxy(&proxy)) {
        *err = "no image writer to memory";
        return false;
      }
      const bool ok = write_levels(*out, path, levels, err);
      out.reset();  // OpenEXR's last writes (the tile offsets) happen here, while the proxy lives
      return ok;
    }
    // A writer without I/O proxies (OIIO 2.4: TGA, HDR): the caller's private temporary, read back.
    const bool ok = write_levels(*out, temp_path, levels, err);
    out.reset();
    if (ok) {
      std::ifstream f(temp_path, std::ios::binary);
      bytes->assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
      if (!f.eof() && f.fail()) *err = "cannot read back " + temp_path;
    }
    std::remove(temp_path.c_str());
    return ok && err->empty();
  } catch (const std::exception& e) {
    *err = first_line(e.what());
    return false;
  }
}

int read_file(const std::string& path, std::vector<float>* px, std::string* err) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    *err = first_line(OIIO::geterror());
    return 0;
  }
  const OIIO::ImageSpec& spec = in->spec();
  px->assign(size_t(spec.width) * spec.height * spec.nchannels, 0.0f);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px->data())) {
    *err = first_line(in->geterror());
    return 0;
  }
  return spec.nchannels;
}

const ahd::OiioModule kModule = {ahd::kOiioModuleAbi, open_image, close_image, seek,     string_attr, int_attr,
                                 read_image,          read_rows,  encode,      read_file};

}  // namespace

// The module's one exported symbol (GetProcAddress finds only exported names on Windows).
#if defined(_WIN32)
#define AHD_OIIO_EXPORT __declspec(dllexport)
#else
#define AHD_OIIO_EXPORT __attribute__((visibility("default")))
#endif
extern "C" AHD_OIIO_EXPORT const void* ahd_oiio_module() { return &kModule; }
