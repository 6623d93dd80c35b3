// The C API (<ahd/ahd.h>) over ahd::convert: copies the input in, catches every exception at the
// boundary (none may cross into C), and owns the result's bytes.
#include <ahd/ahd.h>
#include <ahd/convert.h>

#include <algorithm>
#include <cstring>
#include <new>

#include "sh/sh.h"

struct ahd_result {
  std::vector<ahd::OutputFile> files;
};

namespace {

void set_error(char* error, size_t size, const char* text) {
  if (!error || size == 0) return;
  const size_t n = std::min(size - 1, std::strlen(text));
  std::memcpy(error, text, n);
  error[n] = '\0';
}

ahd::ShImage image_from(const ahd_sh_input& in) {
  if (in.width <= 0 || in.height <= 0 || !ahd::valid_sh_coeffs(in.coeffs) || !in.sh)
    throw ahd::Error("invalid input: width and height must be positive, coeffs 1, 4 or 9, sh not NULL");
  ahd::ShImage img;
  img.width = in.width;
  img.height = in.height;
  img.coeffs = in.coeffs;
  const size_t n = img.texels();
  img.data.assign(in.sh, in.sh + n * size_t(in.coeffs) * 3);
  img.coverage.assign(n, 1);
  if (in.coverage)
    for (size_t i = 0; i < n; ++i) img.coverage[i] = in.coverage[i] ? 1 : 0;
  if (in.normals) img.normals.assign(in.normals, in.normals + n * 3);
  return img;
}

template <typename E>
E enum_in_range(int v, int count, const char* what) {
  if (v < 0 || v >= count) throw ahd::Error(std::string("invalid option ") + what + " = " + std::to_string(v));
  return E(v);
}

ahd::ConversionOptions options_from(const ahd_options& o) {
  ahd::ConversionOptions c;
  if (o.profile) c.profile = o.profile;
  if (o.profile_json) c.profile_json = o.profile_json;
  if (o.ratio >= 0) c.ratio = enum_in_range<ahd::RatioForm>(o.ratio, 2, "ratio");
  c.direction_fit = enum_in_range<ahd::DirectionFit>(o.direction_fit, 2, "direction_fit");
  c.bc6h_quality = enum_in_range<ahd::Bc6hQuality>(o.bc6h_quality, 4, "bc6h_quality");
  c.threads = o.threads;
  c.eps = o.eps;
  c.closed_loop = o.closed_loop != 0;
  c.levels = o.levels;
  c.coverage_plane = o.coverage_plane != 0;
  c.direction = enum_in_range<ahd::DirectionPlanes>(o.direction, 3, "direction");
  c.ambient_threshold = o.ambient_threshold;
  c.container = enum_in_range<ahd::ContainerKind>(o.container, 2, "container");
  c.zstd = o.zstd != 0;
  c.plane_metadata = o.plane_metadata != 0;
  c.measure = enum_in_range<ahd::Measure>(o.measure, 3, "measure");
  return c;
}

}  // namespace

extern "C" {

void ahd_options_init(ahd_options* o) {
  if (!o) return;
  const ahd::ConversionOptions d;
  *o = ahd_options{};
  o->profile = "uncompressed";
  o->profile_json = nullptr;
  o->ratio = -1;
  o->direction_fit = int(d.direction_fit);
  o->bc6h_quality = int(d.bc6h_quality);
  o->threads = d.threads;
  o->eps = d.eps;
  o->closed_loop = d.closed_loop;
  o->levels = d.levels;
  o->coverage_plane = d.coverage_plane;
  o->direction = int(d.direction);
  o->ambient_threshold = d.ambient_threshold;
  o->container = int(d.container);
  o->zstd = d.zstd;
  o->plane_metadata = d.plane_metadata;
  o->measure = int(d.measure);
}

int ahd_convert(const ahd_sh_input* input, const char* name, const ahd_options* options, ahd_result** result,
                char* error, size_t error_size) {
  if (result) *result = nullptr;
  try {
    if (!input || !name || !result) throw ahd::Error("input, name and result must not be NULL");
    ahd_options defaults;
    ahd_options_init(&defaults);
    ahd::Conversion c = ahd::convert(image_from(*input), name, options_from(options ? *options : defaults));
    *result = new ahd_result{std::move(c.files)};
    return 0;
  } catch (const std::bad_alloc&) {
    set_error(error, error_size, "out of memory");
  } catch (const std::exception& e) {
    set_error(error, error_size, e.what());
  } catch (...) {
    set_error(error, error_size, "unknown error");
  }
  return 1;
}

size_t ahd_result_file_count(const ahd_result* r) { return r ? r->files.size() : 0; }

const char* ahd_result_file_name(const ahd_result* r, size_t i) {
  return r && i < r->files.size() ? r->files[i].name.c_str() : nullptr;
}

const unsigned char* ahd_result_file_data(const ahd_result* r, size_t i, size_t* size) {
  if (!r || i >= r->files.size()) {
    if (size) *size = 0;
    return nullptr;
  }
  if (size) *size = r->files[i].bytes.size();
  return r->files[i].bytes.data();
}

void ahd_result_free(ahd_result* r) { delete r; }

const char* ahd_version(void) { return AHD_VERSION_STRING; }

}  // extern "C"
