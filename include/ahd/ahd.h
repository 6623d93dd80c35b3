/* ahdpack's C API, for cook steps that are not C++ (C#, Rust, Python through their FFI).
 * Same contract as <ahd/convert.h>: pure, deterministic, thread-safe on different inputs. Every
 * function that can fail returns 0 on success and non-zero on failure, writing one line (the cause)
 * into `error` (NUL-terminated, truncated to error_size).
 *
 * Linking: the shared library (lib/libahd.so, always installed) exports exactly these functions
 * and the C++ API; load it from any FFI (ctypes, P/Invoke, Rust's libloading) — it brings its own
 * C++ runtime dependency. A C-only program linking the STATIC library (libahd.a, ahdpack::ahd)
 * needs the C++ runtime too: link with g++ (or LINKER_LANGUAGE CXX in CMake), or add
 * -lstdc++ -lm -lpthread to a C link line. The built-in sample's C form is in <ahd/sample.h>
 * (libahd_sample). AHD_VERSION_MAJOR/MINOR/PATCH (<ahd/version.h>) are the headers' version;
 * ahd_version() the linked library's. */
#ifndef AHD_AHD_H
#define AHD_AHD_H
#include <stddef.h>

#include <ahd/export.h>
#include <ahd/version.h>

#ifdef __cplusplus
extern "C" {
#endif

/* An SH lightmap in caller-owned memory, read only during ahd_convert (copied in).
 * sh: width*height*coeffs*3 floats, texel-major: sh[((y*width + x)*coeffs + k)*3 + c], k in the
 *     order Y00, y, z, x (, xy, yz, 3z²−1, xz, x²−y²), radiance projection (docs/conventions.md
 *     "Canonical SH and conventions").
 * coverage: width*height bytes (non-zero = covered), or NULL for every texel covered.
 * normals: width*height*3 unit world-space normals when the SH is in world space, else NULL. */
typedef struct ahd_sh_input {
  int width, height, coeffs; /* coeffs: 1 (L0, a plain lightmap), 4 (L1) or 9 (L2) */
  const float* sh;
  const unsigned char* coverage;
  const float* normals;
} ahd_sh_input;

/* Options; ahd_options_init sets the documented defaults (those of ahd::ConversionOptions).
 * Versioned by size, as KTX-Software's parameter structs: struct_size is the size of the struct the
 * caller was compiled with, and the struct only grows at its end. A library newer than the caller's
 * header takes the members that fit in struct_size and the defaults for the rest; ahd_convert
 * refuses a struct_size that no version of this struct has (0, garbage, or a newer header than
 * the library's). Start from ahd_options_init (or ahd_options_init_size from an FFI), never from
 * uninitialised memory. The members' table: src/api/option_table.cpp. */
typedef struct ahd_options {
  size_t struct_size;       /* sizeof(ahd_options) of the caller's header: set by ahd_options_init */
  const char* profile;      /* standard profile name, default "uncompressed" */
  const char* profile_json; /* or a profile definition (JSON text); NULL = use `profile` */
  int ratio;                /* -1 the profile's form (default), 0 luminance, 1 rgb */
  int direction_fit;        /* 0 linear, 1 refined (default) */
  int bc6h_quality;         /* 0 fast, 1 default, 2 high, 3 max */
  int threads;              /* 0 = all hardware threads */
  double eps;               /* horizon rule, default 0.05 */
  int closed_loop;          /* default 1 */
  int levels;               /* 0 = full mip chain */
  int coverage_plane;       /* default 0 */
  int direction;            /* 0 auto (default), 1 keep, 2 drop */
  double ambient_threshold; /* default 0.01 */
  int container;            /* 0 KTX2 (default), 1 DDS */
  int zstd;                 /* KTX2 supercompression, default 0 */
  int plane_metadata;       /* ahd.* KTX2 key/values, default 1 */
  int measure;              /* 0 off (default), 1 estimate, 2 full */
  double iz_scale;          /* stored I_z = iz_scale x E, default 1 (1/pi: E/pi, what most engines store) */
  int stable_names;         /* plane files NAME.<plane>.<ext> (no content hash), default 0 */
  /* New members only here, at the end (docs/maintaining.md "Adding a conversion option"). */
} ahd_options;

/* Sets every member that fits in struct_size bytes to its default and options->struct_size to
 * struct_size, writing nothing past struct_size bytes (a caller compiled with an older, smaller
 * header is safe). FFI callers pass their mirror's size (ctypes.sizeof). */
AHD_API void ahd_options_init_size(ahd_options* options, size_t struct_size);
/* The same with the size of the struct in the header the caller is compiled with. */
#define ahd_options_init(options) ahd_options_init_size((options), sizeof(ahd_options))

/* The finished conversion: files (planes, then NAME.report.json, then NAME.json
 * — the manifest last: write it last, it commits the set) owned by it. */
typedef struct ahd_result ahd_result;

/* Converts `input` into files named after `name` (a file stem, no folders). On success *result
 * holds the files (free with ahd_result_free); on failure *result is NULL. */
AHD_API int ahd_convert(const ahd_sh_input* input, const char* name, const ahd_options* options, ahd_result** result,
                char* error, size_t error_size);

AHD_API size_t ahd_result_file_count(const ahd_result* result);
/* The i-th file's name (NUL-terminated) and bytes; valid until ahd_result_free. NULL when i is out of range. */
AHD_API const char* ahd_result_file_name(const ahd_result* result, size_t i);
AHD_API const unsigned char* ahd_result_file_data(const ahd_result* result, size_t i, size_t* size);
AHD_API void ahd_result_free(ahd_result* result);

/* The library's version, "MAJOR.MINOR.PATCH". */
AHD_API const char* ahd_version(void);

#ifdef __cplusplus
}
#endif
#endif /* AHD_AHD_H */
