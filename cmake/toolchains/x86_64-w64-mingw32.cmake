# Windows x86-64 from an x86-64 Debian: Debian's MinGW-w64 (g++-mingw-w64-x86-64-posix; the posix
# thread model, which GCC 12 needs for std::thread and std::mutex). The dependencies without a
# MinGW package in Debian (zstd, Imath) are built from Debian's source packages into
# AHD_WIN_DEPS_PREFIX by scripts/cross-windows.sh; nlohmann_json is header-only (the host's
# package). The programs run under Wine (docs/platforms.md "Windows").
set(CMAKE_SYSTEM_NAME Windows)
set(CMAKE_SYSTEM_PROCESSOR x86_64)
set(CMAKE_C_COMPILER x86_64-w64-mingw32-gcc-posix)
set(CMAKE_CXX_COMPILER x86_64-w64-mingw32-g++-posix)
set(CMAKE_RC_COMPILER x86_64-w64-mingw32-windres)
if(NOT AHD_WIN_DEPS_PREFIX)
  set(AHD_WIN_DEPS_PREFIX "$ENV{AHD_WIN_DEPS_PREFIX}")
endif()
set(CMAKE_FIND_ROOT_PATH /usr/x86_64-w64-mingw32 ${AHD_WIN_DEPS_PREFIX})
set(CMAKE_PREFIX_PATH ${AHD_WIN_DEPS_PREFIX})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE BOTH)
# BOTH: nlohmann_json's CMake files are the host's (/usr/share/cmake), header-only.
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
if(AHD_WIN_DEPS_PREFIX)
  set(ENV{PKG_CONFIG_LIBDIR} ${AHD_WIN_DEPS_PREFIX}/lib/pkgconfig)
endif()
# GCC does not align the stack beyond 16 bytes on Win64, yet spills AVX registers with aligned
# moves (GCC bug 54412): the AVX2/AVX-512 paths would crash. The assembler makes them unaligned.
add_compile_options(-Wa,-muse-unaligned-vector-move)
set(CMAKE_CROSSCOMPILING_EMULATOR wine)
