// EXR files decoded by OpenEXR directly, from the bytes already read once (image_file.h's rule):
// the reader of every SH lightmap, without OpenImageIO's start-up cost (docs/performance-real.md
// "Process start"). Internal to src/image; image_io.h's readers choose it for EXR files.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "image/image_io.h"

namespace ahd {

// True when `bytes` start with the OpenEXR magic number.
bool is_exr_bytes(const std::vector<uint8_t>& bytes);

// One EXR file opened from memory. `bytes` must outlive the reader. Not thread safe (one caller);
// decoding itself runs on thread pools (ZIP chunks on ahd's, image/exr_zip.h; the other codecs on
// OpenEXR's, for files big enough), whose counts change no decoded value.
class ExrReader {
 public:
  // Opens the file's headers (every part). Throws ahd::Error("<path>: cannot read image (…)") on a
  // malformed file. Sizes are checked by info() (check_declared_image) before pixels are sized.
  ExrReader(const std::string& path, const std::vector<uint8_t>& bytes);
  // The headers from the first bytes of a file of `file_bytes` bytes (`bytes` may be the whole
  // file or its beginning): info() checks sizes against the whole file's size, as above. Reading
  // pixels past the bytes given throws. Throws as above when the headers are not within `bytes`.
  ExrReader(const std::string& path, const std::vector<uint8_t>& bytes, uint64_t file_bytes);
  ~ExrReader();

  // Every part's name ("" when unnamed), in file order.
  std::vector<std::string> part_names() const;

  // False when `part` holds samples this reader leaves to OpenImageIO (integer or subsampled
  // channels, whose conversion to float OpenImageIO defines), true for half and float parts.
  // Throws naming the part count when there is no such part.
  bool handles(int part) const;

  // The header of `part` as OpenImageIO reports it (channel order: per layer R, G, B, A, …, then
  // by name; oiio:ColorSpace "Linear" unless the file names one), checked with
  // check_declared_image before anything is sized by it. Throws ahd::Error.
  ImageFileInfo info(int part) const;

  // Rows y0..y1−1 of `part`'s data window as floats, channels in info()'s order, into `dst`
  // ((y1−y0)·width·channels floats). Throws ahd::Error("<path>: cannot read pixels (…)").
  void read_rows(int part, int y0, int y1, float* dst);

  // The height of one band of decoding: the tile height (tiled parts) or 64 rows.
  int band_rows(int part) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ahd
