// OpenImageIO behind dlopen: the image formats other than half/float EXR (PNG, TGA, HDR, integer
// EXR) and every image write go through a small module (libahd_oiio.so, src/oiio/module.cpp)
// loaded on first use, so a process that reads EXR only never loads OpenImageIO's ≈ 260 shared
// libraries (docs/performance-real.md "Process start"). The module is a thin layer over
// OpenImageIO calls, with no ahdpack state of its own: every check and every error message stays
// on this side. Internal to src/image.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace ahd {

// Bumped whenever OiioModule changes: a module of another build is refused, not called.
constexpr int kOiioModuleAbi = 1;

// One part's header as OpenImageIO reports it.
struct OiioSpec {
  int width = 0, height = 0, nchannels = 0, x = 0, y = 0, z = 0, depth = 1;
  int tile_width = 0, tile_height = 0;
  bool deep = false;
  uint64_t pixel_bytes = 0;  // native bytes of one texel, all channels
  std::string codec;         // the "compression" attribute, else the format's name
  std::vector<std::string> channel_names;
  bool is_float = false;              // every channel half, float or double
  std::string color_space;            // "oiio:ColorSpace"
  std::vector<float> chromaticities;  // 8 floats when declared
  std::string part_name;              // "oiio:subimagename"
};

// An image to encode: `px` holds width·height·channels floats.
struct OiioEncodeLevel {
  int width = 0, height = 0, channels = 0;
  const float* px = nullptr;
  std::vector<std::string> channel_names;  // empty: the writer's defaults
  int format = 0;                          // 0 float, 1 half, 2 uint8
  int tile = 0;                            // tile size, 0 = scanlines
  std::vector<std::pair<std::string, std::string>> string_attrs;
  std::vector<std::pair<std::string, int>> int_attrs;
};

// The module's calls. Handles come from open() and go to close(). Errors: false / null with the
// first line of OpenImageIO's message in *err. None throws. Not thread safe per handle.
struct OiioModule {
  int abi;
  // Opens `bytes` (the whole file, read once by the caller; must outlive the handle) as an image.
  void* (*open)(const std::string& path, const uint8_t* bytes, size_t size, bool unassociated_alpha, std::string* err);
  void (*close)(void* h);
  // Positions on part/mip and fills *spec; false when there is no such part/mip.
  bool (*seek)(void* h, int part, int mip, OiioSpec* spec);
  // Attributes of the current part/mip.
  std::string (*string_attr)(void* h, const std::string& name, const std::string& fallback);
  int (*int_attr)(void* h, const std::string& name, int fallback);
  // All channels of part/mip as floats into dst (width·height·channels).
  bool (*read_image)(void* h, int part, int mip, float* dst, std::string* err);
  // Rows y0..y1−1 (of the data window) of `part` as floats into dst, by tiles or scanlines.
  bool (*read_rows)(void* h, int part, int y0, int y1, float* dst, std::string* err);
  // Encodes one image (levels.size() == 1) or a mip chain (EXR, "Plain Texture", round down) by
  // the extension of `path`; a writer without memory output writes `temp_path` and reads it back.
  bool (*encode)(const std::string& path, const std::string& temp_path, const std::vector<OiioEncodeLevel>& levels,
                 std::vector<uint8_t>* out, std::string* err);
  // OpenImageIO alone reading a file from disk into floats (the bench's baseline); returns channels.
  int (*read_file)(const std::string& path, std::vector<float>* px, std::string* err);
};

// The module, loaded on first call (thread safe): libahd_oiio.so beside the executable's library
// folder (<prefix>/<libdir>/ahdpack/ for <prefix>/bin/ahdpack), else the build tree's. Throws
// ahd::Error("<why>: needs OpenImageIO, whose module cannot be loaded (<module path>: <cause>)"),
// `why` being the file that needed it, when the module is missing or of another build.
const OiioModule& oiio_module(const std::string& why);

}  // namespace ahd
