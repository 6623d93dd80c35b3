// The C API (<ahd/ahd.h>) over ahd::convert: copies the input in, catches every exception at the
// boundary (none may cross into C), and owns the result's bytes.
#include <ahd/ahd.h>
#include <ahd/convert.h>

#include <algorithm>
#include <cstddef>
#include <cmath>
#include <cstring>
#include <new>

#include "api/option_table.h"
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
  if (in.normals) {
    img.normals.assign(in.normals, in.normals + n * 3);
    // As the CLI's normal maps (bakers/baker_layout.cpp check_normals): a covered texel's normal must
    // have a length (a zero one normalises to NaN: a black texel); non-finite ones: check_sh_image.
    for (size_t i = 0; i < n; ++i) {
      const double x = img.normals[i * 3], y = img.normals[i * 3 + 1], z = img.normals[i * 3 + 2];
      const double len = std::sqrt(x * x + y * y + z * z);
      if (img.coverage[i] && std::isfinite(len) && !(len > 1e-6))
        throw ahd::Error("zero-length normal at texel (" + std::to_string(i % size_t(in.width)) + ", " +
                         std::to_string(i / size_t(in.width)) + ")");
    }
  }
  return img;
}

// The smallest struct_size accepted: struct_size and the first member (every later member of an
// older, smaller struct takes its default).
constexpr size_t kMinOptionsSize = offsetof(ahd_options, profile) + sizeof(const char*);

bool valid_options_size(size_t n) {
  return n >= kMinOptionsSize && n <= sizeof(ahd_options) && n % alignof(ahd_options) == 0;
}

// The caller's options (of its struct_size) as the C++ options: the members within struct_size,
// the defaults for the rest, each checked by its row of the option table.
ahd::ConversionOptions options_from(const ahd_options& given) {
  const size_t n = given.struct_size;
  if (!valid_options_size(n))
    throw ahd::Error("invalid ahd_options.struct_size " + std::to_string(n) + ": set it with ahd_options_init (this library takes " +
                     std::to_string(kMinOptionsSize) + " to " + std::to_string(sizeof(ahd_options)) + " bytes)");
  ahd_options o;
  ahd_options_init_size(&o, sizeof o);
  std::memcpy(static_cast<void*>(&o), &given, n);
  ahd::ConversionOptions c;
  for (const ahd::OptionRow& r : ahd::option_table())
    if (r.c_offset + r.c_size <= n) r.from_c(o, c);
  return c;
}

}  // namespace

extern "C" {

void ahd_options_init_size(ahd_options* o, size_t struct_size) {
  if (!o || struct_size < sizeof(size_t)) return;
  ahd_options d;
  std::memset(static_cast<void*>(&d), 0, sizeof d);  // padding too: the caller's bytes are all defined
  for (const ahd::OptionRow& r : ahd::option_table()) r.c_default(d);
  d.struct_size = struct_size;
  // A caller compiled with a newer, larger struct: its members past ours stay as they are, and
  // ahd_convert refuses the size.
  std::memcpy(static_cast<void*>(o), &d, std::min(struct_size, sizeof d));
}

int ahd_convert(const ahd_sh_input* input, const char* name, const ahd_options* options, ahd_result** result,
                char* error, size_t error_size) {
  if (result) *result = nullptr;
  try {
    if (!input || !name || !result) throw ahd::Error("input, name and result must not be NULL");
    ahd::Conversion c = ahd::convert(image_from(*input), name, options ? options_from(*options) : ahd::ConversionOptions{});
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
