// Image files in and out (OpenEXR, the OpenImageIO module). The only place that touches image
// files; whole files and publication are files/file_io.h and files/output_set.h.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/image.h"

namespace ahd {

// What a file holds, read without its pixels: size, channel names, per-channel float-ness.
struct ImageFileInfo {
  int width = 0;
  int height = 0;
  std::vector<std::string> channel_names;
  bool is_float = false;   // every channel is half or float
  std::string color_space; // OIIO's "oiio:ColorSpace" (may be empty)
  std::vector<float> chromaticities;  // EXR "chromaticities" when declared: R, G, B, white (x, y) each
  std::vector<std::string> parts;  // every part (OIIO subimage) of the file by name, "" if unnamed
};

// Reads the header of one part (subimage; multi-part EXR) of an image file. Throws
// ahd::Error("<path>: <cause>") when the file is missing or unreadable or has no such part, or
// when the header claims more than the file can hold or the size limit allows
// (check_declared_image). Safe on untrusted files. Every reader below reads the file once into
// memory, so a file replaced while it is read gives an error or the old or new file, never a
// header from one and pixels from the other.
ImageFileInfo read_image_info(const std::string& path, int part = 0);

// A scope on this thread (as files/input_record.h's RecordInputs) in which read_image_info
// answers each (path, part) from its first answer: one conversion asks for its input's header
// several times (the layout's detection, the bake's pages), each a read and a parse of the file's
// head. A repeated answer still checks that the file exists and notes it as read (the same
// record, the same "file not found" if it went away); errors are never kept. Scopes nest, the
// inner one starting empty. Not copyable.
class ImageInfoScope {
 public:
  ImageInfoScope();
  ~ImageInfoScope();
  ImageInfoScope(const ImageInfoScope&) = delete;
  ImageInfoScope& operator=(const ImageInfoScope&) = delete;
  struct Memo;  // image_io.cpp

 private:
  Memo* previous_;
  Memo* memo_;
};

// Reads every channel of one part (subimage) / mip 0 as floats (8-bit data is scaled to [0,1]; no
// colour conversion). Throws ahd::Error on failure.
ImageF read_image(const std::string& path, ImageFileInfo* info = nullptr, int part = 0);

// Reads every channel of one part / mip 0 as floats in bands of rows, never the whole image at once:
// fn(y0, y1, rows) receives rows y0..y1−1 (0 = the top row of the data window), (y1−y0)·width·
// channels floats. Bands follow the file's tiles (tiled files) or 64-row chunks (scanline files),
// so memory is the caller's destination plus one band. Same values and errors as read_image.
// The file is read once: `on_header` (optional) sees the header the rows will have, before the
// first band, so a caller sizes its destination from it (never from an earlier read_image_info,
// which a file replaced in between would contradict).
void read_image_rows(const std::string& path, int part, ImageFileInfo* info,
                     const std::function<void(int y0, int y1, const float* rows)>& fn,
                     const std::function<void(const ImageFileInfo&)>& on_header = {});

// A float image as the bytes of an EXR (half when `half_float`, else float), or PNG/TGA/HDR by
// the extension of `path` (8-bit formats clamp to [0,1] and round), in memory. Channel names default
// to R,G,B,A / Y. Throws ahd::Error naming `path`.
std::vector<uint8_t> encode_image(const std::string& path, const ImageF& img, bool half_float = false,
                                  const std::vector<std::string>& channel_names = {});

// encode_image published at `path` by files/output_set.h's publish_file: a temporary in the same
// folder, every write checked (a full disk is an error), fsync, rename; the previous file stays
// whole on any failure or SIGINT/SIGTERM.
void write_image(const std::string& path, const ImageF& img, bool half_float = false,
                 const std::vector<std::string>& channel_names = {});

}  // namespace ahd
