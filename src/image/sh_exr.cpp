#include "image/sh_exr.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <map>

#include "core/error.h"
#include "core/parallel.h"
#include "image/colour_space.h"
#include "image/image_io.h"

namespace ahd {
namespace {

const char* kRgb[3] = {"R", "G", "B"};

std::string sh_channel(int k, int c) { return "sh" + std::to_string(k) + "." + kRgb[c]; }

}  // namespace

namespace {

// One row of sanitise_sh with `per` floats a texel (kPer: known at compile time, 0 = `per`).
// |x| ≤ kMaxShMagnitude and finite is "the magnitude's bits ≤ those of kMaxShMagnitude" (NaN and
// ±Inf have larger ones), x == 0 is "magnitude bits 0": integer compares without branches.
template <size_t kPer>
size_t sanitise_row(float* t, uint8_t* coverage, size_t texels, size_t per_runtime, bool derive_coverage) {
  const size_t per = kPer ? kPer : per_runtime;
  uint32_t max_bits;
  std::memcpy(&max_bits, &kMaxShMagnitude, 4);
  size_t non_finite = 0;
  for (size_t i = 0; i < texels; ++i, t += per) {
    uint32_t worst = 0, any = 0;
    for (size_t k = 0; k < per; ++k) {
      uint32_t b;
      std::memcpy(&b, &t[k], 4);
      b &= 0x7FFFFFFFu;
      worst = std::max(worst, b);
      any |= b;
    }
    if (worst > max_bits) {
      std::fill(t, t + per, 0.0f);
      coverage[i] = 0;
      ++non_finite;
    } else if (derive_coverage && any == 0) {
      coverage[i] = 0;
    }
  }
  return non_finite;
}

}  // namespace

void sanitise_sh(ShImage& img, bool derive_coverage, ReadStats* stats) {
  const size_t per = size_t(img.coeffs) * 3, w = size_t(img.width);
  std::vector<size_t> non_finite(size_t(img.height), 0);  // per row, summed in order after
  auto row = per == 3 ? sanitise_row<3> : per == 12 ? sanitise_row<12> : per == 27 ? sanitise_row<27> : sanitise_row<0>;
  parallel_for(size_t(img.height), 0, 16, [&](size_t y) {
    non_finite[y] = row(img.texel(y * w), img.coverage.data() + y * w, w, per, derive_coverage);
  });
  if (stats) {
    for (size_t n : non_finite) stats->non_finite_texels += n;
    stats->coverage_derived = derive_coverage;
  }
}

void check_not_flooded(const std::string& path, const ShImage& img, size_t non_finite) {
  if (non_finite == 0) return;
  for (uint8_t c : img.coverage)
    if (c) return;
  // A NaN/Inf flood is a broken file, not a lightmap to convert to black (issues 15, 26).
  throw file_error(path, "no finite texel (NaN, Inf or beyond 1e18 everywhere a chart covers)");
}

ShImage read_canonical_sh(const std::string& path, ReadStats* stats, const std::string& input_space) {
  // One read of the file: the header that sizes the SH image is the header of the rows written
  // into it (issue 26: a file replaced between two opens overflowed the heap).
  ShImage img;
  int coeffs = 0, src_of[kShCoeffsL2 * 3] = {}, channels = 0, ci = -1, nx = 0, ny = 0, nz = 0;
  bool has_coverage = false, has_normals = false;
  SourceSpace space;
  Matrix3 to_working{};
  std::atomic<size_t> bad_coverage{0};
  auto on_header = [&](const ImageFileInfo& info) {
    if (!info.is_float) throw file_error(path, "SH lightmaps must be half or float EXR data (found 8-bit or integer channels)");
    // The layout path's rule too: the declared space (or --input-space) is converted to the
    // working space, never taken for it (issue 26: a canonical EXR declaring Rec.2020 was read as
    // Rec.709). Checked here, before any row is read.
    space = input_space.empty() ? declared_space(info, path) : parse_input_space(input_space);
    if (space.srgb_encoded())
      throw file_error(path,
                       "SH coefficients are signed and linear in radiance: an sRGB encoding cannot hold them "
                       "(give --input-space with the linear space they are in)");
    to_working = working_space_matrix(space, path);  // a space OpenColorIO cannot convert: refused before the rows
    std::map<std::string, int> index;
    for (size_t c = 0; c < info.channel_names.size(); ++c) index[info.channel_names[c]] = int(c);
    if (index.count(sh_channel(8, 2))) coeffs = 9;
    else if (index.count(sh_channel(3, 2))) coeffs = 4;
    else if (index.count(sh_channel(0, 2)) && !index.count(sh_channel(1, 0))) coeffs = 1;
    else throw file_error(path, "no SH channels: expected sh0.R sh0.G sh0.B (L0), … sh3.B (L1) or … sh8.B (L2)");
    for (int k = 0; k < coeffs; ++k)
      for (int c = 0; c < 3; ++c)
        if (!index.count(sh_channel(k, c))) throw file_error(path, "missing channel " + sh_channel(k, c));
    if (coeffs < 9 && index.count(sh_channel(coeffs, 0)))
      throw file_error(path, coeffs == 4 ? "incomplete L2 channel set (sh4..sh8 partly present)" : "incomplete L1 channel set (sh1..sh3 partly present)");
    // Rows arrive in bands straight from OpenImageIO into the SH image: the file is never held
    // whole in a second buffer (or precision) beside it.
    img = make_sh_image(info.width, info.height, coeffs);
    for (int k = 0; k < coeffs; ++k)
      for (int c = 0; c < 3; ++c) src_of[k * 3 + c] = index[sh_channel(k, c)];
    channels = int(info.channel_names.size());
    has_coverage = index.count("coverage") != 0;
    ci = has_coverage ? index["coverage"] : -1;
    has_normals = index.count("normal.X") && index.count("normal.Y") && index.count("normal.Z");
    nx = has_normals ? index["normal.X"] : 0, ny = has_normals ? index["normal.Y"] : 0,
    nz = has_normals ? index["normal.Z"] : 0;
    if (has_normals) img.normals.resize(img.texels() * 3);
  };
  read_image_rows(path, 0, nullptr, [&](int y0, int y1, const float* rows) {
    const int nv = coeffs * 3, w = img.width;
    parallel_for(size_t(y1 - y0), 0, 4, [&](size_t r) {
      const size_t first = (size_t(y0) + r) * w;
      const float* row = rows + r * size_t(w) * channels;
      for (int x = 0; x < w; ++x) {
        const float* src = row + size_t(x) * channels;
        float* dst = img.texel(first + x);
        for (int v = 0; v < nv; ++v) dst[v] = src[src_of[v]];
        if (has_coverage) {
          img.coverage[first + x] = src[ci] > 0.5f;
          if (!std::isfinite(src[ci])) bad_coverage.fetch_add(1, std::memory_order_relaxed);
        }
      }
    });
    if (!has_normals) return;
    for (size_t i = size_t(y0) * w; i < size_t(y1) * w; ++i) {  // in order: the first bad normal is named
      const float* src = rows + (i - size_t(y0) * w) * channels;
      double n[3] = {src[nx], src[ny], src[nz]};
      const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      if (!(len > 1e-6) || !std::isfinite(len)) {
        if (img.coverage[i] || !has_coverage)
          throw file_error(path, "zero-length or non-finite normal at texel (" +
                                     std::to_string(i % img.width) + ", " + std::to_string(i / img.width) + ")");
        n[0] = 0, n[1] = 0, n[2] = 1;
      } else {
        for (double& v : n) v /= len;
      }
      for (int a = 0; a < 3; ++a) img.normals[i * 3 + a] = float(n[a]);
    }
  }, on_header);
  // A NaN coverage would read as "gutter" everywhere and give an empty map without a word.
  if (const size_t bad = bad_coverage.load())
    throw file_error(path, "coverage channel is NaN or infinite at " + std::to_string(bad) +
                               " texels (it must be 1 where a chart covers, 0 in gutters)");
  ReadStats local;
  ReadStats& st = stats ? *stats : local;
  if (!space.working_primaries()) {  // the working space's files are read untouched (same bytes)
    apply_matrix(img, to_working);
    st.input_space = space.describe();
  }
  const size_t before = st.non_finite_texels;
  sanitise_sh(img, !has_coverage, &st);
  check_not_flooded(path, img, st.non_finite_texels - before);
  return img;
}

void write_canonical_sh(const std::string& path, const ShImage& img) {
  const bool normals = !img.normals.empty();
  const int channels = img.coeffs * 3 + 1 + (normals ? 3 : 0);
  ImageF px(img.width, img.height, channels);
  std::vector<std::string> names;
  for (int k = 0; k < img.coeffs; ++k)
    for (int c = 0; c < 3; ++c) names.push_back(sh_channel(k, c));
  names.push_back("coverage");
  if (normals) {
    names.push_back("normal.X");
    names.push_back("normal.Y");
    names.push_back("normal.Z");
  }
  for (size_t i = 0; i < img.texels(); ++i) {
    float* dst = px.data.data() + i * channels;
    const float* src = img.texel(i);
    for (int k = 0; k < img.coeffs * 3; ++k) dst[k] = src[k];
    dst[img.coeffs * 3] = img.coverage[i] ? 1.0f : 0.0f;
    if (normals)
      for (int a = 0; a < 3; ++a) dst[img.coeffs * 3 + 1 + a] = img.normals[i * 3 + a];
  }
  write_image(path, px, false, names);
}

}  // namespace ahd
