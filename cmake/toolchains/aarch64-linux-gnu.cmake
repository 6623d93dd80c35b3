# Arm64 Linux from an x86-64 Debian: Debian's cross compiler (g++-aarch64-linux-gnu) and the arm64
# -dev packages installed through multiarch (dpkg --add-architecture arm64), which put their
# libraries in /usr/lib/aarch64-linux-gnu and share /usr/include. The programs run under
# qemu-aarch64 (qemu-user) with the arm64 libraries of multiarch. scripts/cross-arm64.sh
# installs the packages and runs the build (docs/platforms.md).
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)
# Libraries and packages' CMake files of the target only (…/aarch64-linux-gnu/…), headers from
# /usr/include (multiarch shares them), programs from the host.
set(CMAKE_FIND_ROOT_PATH /usr/aarch64-linux-gnu)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
# pkg-config (zstd): the arm64 .pc files, never the host's.
set(ENV{PKG_CONFIG_LIBDIR} /usr/lib/aarch64-linux-gnu/pkgconfig:/usr/share/pkgconfig)
# AHD_ARM64_SYSROOT: arm64 -dev packages that multiarch cannot install beside the host's amd64 ones
# (libopenexr-dev, libopencolorio-dev: same files, different contents), unpacked there with dpkg -x
# by scripts/cross-arm64.sh. Their runtime libraries are installed through multiarch as usual.
# (Passed on to try_compile, which reads this file again: else it resets PKG_CONFIG_LIBDIR.)
list(APPEND CMAKE_TRY_COMPILE_PLATFORM_VARIABLES AHD_ARM64_SYSROOT)
if(AHD_ARM64_SYSROOT)
  list(APPEND CMAKE_FIND_ROOT_PATH ${AHD_ARM64_SYSROOT})
  set(ENV{PKG_CONFIG_LIBDIR} ${AHD_ARM64_SYSROOT}/usr/lib/aarch64-linux-gnu/pkgconfig:$ENV{PKG_CONFIG_LIBDIR})
  set(CMAKE_EXE_LINKER_FLAGS_INIT "-Wl,-rpath-link,${AHD_ARM64_SYSROOT}/usr/lib/aarch64-linux-gnu")
  set(CMAKE_SHARED_LINKER_FLAGS_INIT "-Wl,-rpath-link,${AHD_ARM64_SYSROOT}/usr/lib/aarch64-linux-gnu")
  set(CMAKE_MODULE_LINKER_FLAGS_INIT "-Wl,-rpath-link,${AHD_ARM64_SYSROOT}/usr/lib/aarch64-linux-gnu")
endif()
# The loader and libc of libc6:arm64 (multiarch, /lib/aarch64-linux-gnu), not the cross sysroot's: the
# arm64 -dev packages pull in libc6:arm64, and a process mixing the two glibc builds (ld.so of
# libc6-arm64-cross 2.36-8, libc.so.6 of libc6:arm64 2.36-9) hangs in its first pthread_create.
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64 -L /)
