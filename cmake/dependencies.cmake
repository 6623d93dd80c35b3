# What the targets need, from Debian's packages (scripts/setup.sh installs them).
find_package(Threads REQUIRED)
find_package(Imath CONFIG REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(ZSTD REQUIRED IMPORTED_TARGET GLOBAL libzstd)
find_package(nlohmann_json CONFIG REQUIRED)

# AHD_LIBRARY_ONLY: the library ahd, the sample and the platform tests need nothing more
# (docs/platforms.md "Library-only builds").
if(AHD_LIBRARY_ONLY)
  return()
endif()

# EXR files are read by OpenEXR directly (src/image/exr_read.cpp): no OpenImageIO start-up for them.
find_package(OpenEXR CONFIG REQUIRED)
# Their ZIP chunks are inflated by libdeflate where it is installed (src/image/exr_zip.cpp: 1.6× zlib's
# speed); OpenEXR inflates them otherwise, to the same values (the cross builds do without it).
pkg_check_modules(DEFLATE QUIET IMPORTED_TARGET GLOBAL libdeflate)
if(AHD_OIIO_MODULE)
find_package(OpenImageIO CONFIG REQUIRED)
# Debian's OpenImageIO config names /usr/include/opencv4 even when OpenCV's headers are not
# installed; we never include OpenCV, so drop paths that do not exist.
get_target_property(_oiio_inc OpenImageIO::OpenImageIO INTERFACE_INCLUDE_DIRECTORIES)
set(_oiio_inc_ok)
foreach(_d ${_oiio_inc})
  if(EXISTS "${_d}")
    list(APPEND _oiio_inc_ok "${_d}")
  endif()
endforeach()
set_target_properties(OpenImageIO::OpenImageIO PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${_oiio_inc_ok}")
endif()
# Meshes (--mesh). pkg-config (-lassimp) rather than Debian's assimpConfig.cmake, which adds
# draco::draco, minizip and a static librt.a to every consumer's link line although the shared
# libassimp.so already carries its own dependencies.
pkg_check_modules(ASSIMP REQUIRED IMPORTED_TARGET GLOBAL assimp)
# Colour spaces of inputs (image/colour_space.cpp): OpenColorIO 2.1's raw config and builtin transforms.
# Debian ships no CMake config for it, only OpenColorIO.pc. Linked to ahd_io only.
if(AHD_OCIO)
  pkg_check_modules(OCIO REQUIRED IMPORTED_TARGET GLOBAL OpenColorIO>=2.1)
endif()
if(AHD_BUILD_CLI)
  find_package(CLI11 CONFIG QUIET)  # header-only; Debian ships the headers in /usr/include
endif()
