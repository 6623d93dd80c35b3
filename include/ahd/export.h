/* AHD_API marks what the shared libraries export (libahd.so, libahd_sample.so): the C API and the
 * C++ API of <ahd/convert.h>, <ahd/types.h> and <ahd/sample.h>. Everything else is compiled with
 * hidden visibility. For the static libraries it changes nothing. */
#ifndef AHD_EXPORT_H
#define AHD_EXPORT_H
#if defined(_WIN32)
#if defined(AHD_BUILDING_LIBRARY)
#define AHD_API __declspec(dllexport)
#elif defined(AHD_SHARED)
#define AHD_API __declspec(dllimport)
#else
#define AHD_API
#endif
#elif defined(__GNUC__) || defined(__clang__)
#define AHD_API __attribute__((visibility("default")))
#else
#define AHD_API
#endif
#endif /* AHD_EXPORT_H */
