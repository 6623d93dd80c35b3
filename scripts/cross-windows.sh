#!/usr/bin/env bash
# Windows x86-64: cross-build the library with Debian's MinGW-w64, run its unit tests and the byte
# comparison under Wine (docs/platforms.md "Windows").
#   bash scripts/cross-windows.sh [--no-install] [--bytes-only|--tests-only]
# Installs (as root, unless --no-install) MinGW-w64 (posix threads) and Wine; builds zstd and Imath,
# which Debian does not ship for MinGW, from Debian's source packages (apt-get source; a deb-src
# line for the system's suites is added when none is configured) into build-win/deps/prefix; builds
# build-win/ (AHD_LIBRARY_ONLY, cmake/toolchains/x86_64-w64-mingw32.cmake) and the x86-64 reference
# build-x86/; runs ahd_platform_tests.exe under Wine in a fresh WINEPREFIX, then
# ahd_platform_bytes.exe, whose planes and manifests must equal the x86-64 ones byte for byte.
set -euo pipefail
cd "$(dirname "$0")/.."
install=1 tests=1 bytes=1 library_only=0 deps_only=0
for a in "$@"; do
  case $a in
    --no-install) install=0 ;;
    --library-only) library_only=1 ;;
    --deps-only) deps_only=1 ;;
    --bytes-only) tests=0 ;;
    --tests-only) bytes=0 ;;
    *) sed -n '2,10p' "$0" >&2; exit 2 ;;
  esac
done
build=build-win
deps=$PWD/$build/deps
prefix=$deps/prefix
toolchain=$PWD/cmake/toolchains/x86_64-w64-mingw32.cmake

if [ $install = 1 ] && ! { command -v x86_64-w64-mingw32-g++-posix && command -v wine && [ -d /usr/src/googletest ] \
    && [ -f /usr/x86_64-w64-mingw32/lib/libz.a ] && [ -d /usr/include/utf8cpp ] && [ -d /usr/include/CLI ]; } >/dev/null; then
  apt-get update -q
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends g++-mingw-w64-x86-64-posix wine wine64 \
    nlohmann-json3-dev googletest dpkg-dev ninja-build cmake pkg-config libz-mingw-w64-dev libutfcpp-dev libcli11-dev
fi

# The dependencies Debian does not ship for MinGW, from Debian's source packages, static, into
# $prefix (docs/platforms.md "Windows"): zstd and Imath for the library; for the file edge and the
# CLI also OpenEXR (zlib is Debian's libz-mingw-w64-dev), minizip (from zlib's source package: Assimp
# reads zip archives through it) and Assimp with only the importers ahdpack reads (glTF, OBJ, FBX).
# Each is built once (its stamp file in $deps).
fetch_sources() {  # apt-get source, adding a deb-src line for the system's suite when apt has none
  if ! grep -rqs '^Types:.*deb-src\|^deb-src' /etc/apt/sources.list /etc/apt/sources.list.d/; then
    [ $install = 1 ] || { echo "cross-windows: no deb-src line in apt's sources (needed for $*)" >&2; exit 1; }
    suite=$(. /etc/os-release && echo "$VERSION_CODENAME")
    printf 'Types: deb-src\nURIs: http://deb.debian.org/debian\nSuites: %s\nComponents: main\nSigned-By: /usr/share/keyrings/debian-archive-keyring.gpg\n' \
      "$suite" > /etc/apt/sources.list.d/ahdpack-deb-src.sources
    apt-get update -q
  fi
  (cd "$deps" && apt-get source -q "$@" >/dev/null)
}
source_dir() { find "$deps" -maxdepth 1 -type d -name "$1-[0-9]*" | sort | tail -1; }
cmake_dep() {  # cmake_dep NAME SOURCE_DIR [CMAKE ARGS...]: configure, build and install one dependency
  local name=$1 src=$2; shift 2
  local start; start=$(date +%s)
  cmake -S "$src" -B "$deps/$name-build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_TOOLCHAIN_FILE="$toolchain" \
    -DCMAKE_INSTALL_PREFIX="$prefix" -DBUILD_SHARED_LIBS=OFF "$@" >"$deps/$name-configure.log"
  nice -n 19 cmake --build "$deps/$name-build" -j2 --target install >"$deps/$name-build.log"
  echo "cross-windows: $name built in $(( $(date +%s) - start )) s"
  touch "$deps/$name.stamp"
}
mkdir -p "$deps"
if [ ! -f "$deps/zstd.stamp" ]; then
  [ -n "$(source_dir libzstd)" ] || fetch_sources libzstd
  cmake_dep zstd "$(source_dir libzstd)/build/cmake" -DZSTD_BUILD_PROGRAMS=OFF -DZSTD_BUILD_SHARED=OFF \
    -DZSTD_BUILD_TESTS=OFF -DZSTD_MULTITHREAD_SUPPORT=OFF
fi
if [ ! -f "$deps/imath.stamp" ]; then
  [ -n "$(source_dir imath)" ] || fetch_sources imath
  cmake_dep imath "$(source_dir imath)" -DBUILD_TESTING=OFF -DPYTHON=OFF
fi
if [ $library_only = 0 ] && [ ! -f "$deps/openexr.stamp" ]; then
  [ -n "$(source_dir openexr)" ] || fetch_sources openexr
  cmake_dep openexr "$(source_dir openexr)" -DBUILD_TESTING=OFF -DOPENEXR_BUILD_TOOLS=OFF \
    -DOPENEXR_INSTALL_EXAMPLES=OFF -DOPENEXR_INSTALL_TOOLS=OFF -DZLIB_LIBRARY=/usr/x86_64-w64-mingw32/lib/libz.a
fi
if [ $library_only = 0 ] && [ ! -f "$deps/minizip.stamp" ]; then
  # zlib's contrib/minizip has no CMake build: the unzip half (all Assimp uses) is three files.
  [ -n "$(source_dir zlib)" ] || fetch_sources zlib
  mz=$(source_dir zlib)/contrib/minizip
  mkdir -p "$deps/minizip-build" "$prefix/include/minizip" "$prefix/lib/pkgconfig"
  for f in ioapi unzip iowin32; do
    x86_64-w64-mingw32-gcc-posix -O2 -c "$mz/$f.c" -o "$deps/minizip-build/$f.o"
  done
  x86_64-w64-mingw32-ar rcs "$prefix/lib/libminizip.a" "$deps/minizip-build"/*.o
  cp "$mz"/{ioapi,unzip,iowin32,crypt}.h "$prefix/include/minizip/"
  printf 'prefix=%s\nName: minizip\nDescription: unzip part of zlib contrib/minizip\nVersion: 1.2.13\nCflags: -I${prefix}/include/minizip\nLibs: -L${prefix}/lib -lminizip -lz\n' \
    "$prefix" > "$prefix/lib/pkgconfig/minizip.pc"
  touch "$deps/minizip.stamp"
fi
if [ $library_only = 0 ] && [ ! -f "$deps/assimp.stamp" ]; then
  [ -n "$(source_dir assimp)" ] || fetch_sources assimp
  # Debian's source uses the system's utf8cpp (header-only; the host's libutfcpp-dev, copied so
  # that no host header shadows MinGW's).
  mkdir -p "$prefix/include/utf8cpp" && cp -r /usr/include/utf8cpp/. "$prefix/include/utf8cpp/"
  # Its patch use-system-libdraco asks for draco's CMake package whether or not glTF's Draco
  # decoding is on (it is off here: ASSIMP_ENABLE_DRACO undefined): an empty package answers.
  mkdir -p "$deps/no-draco" && : > "$deps/no-draco/dracoConfig.cmake"
  cmake_dep assimp "$(source_dir assimp)" -DASSIMP_BUILD_TESTS=OFF -DASSIMP_BUILD_ASSIMP_TOOLS=OFF \
    -DASSIMP_BUILD_SAMPLES=OFF -DASSIMP_BUILD_ZLIB=OFF -DASSIMP_NO_EXPORT=ON -DASSIMP_INSTALL_PDB=OFF \
    -DASSIMP_WARNINGS_AS_ERRORS=OFF -DASSIMP_BUILD_ALL_IMPORTERS_BY_DEFAULT=OFF -DASSIMP_BUILD_OBJ_IMPORTER=ON \
    -DASSIMP_BUILD_GLTF_IMPORTER=ON -DASSIMP_BUILD_FBX_IMPORTER=ON -DASSIMP_BUILD_DRACO=OFF \
    -DZLIB_LIBRARY=/usr/x86_64-w64-mingw32/lib/libz.a -DCMAKE_CXX_FLAGS="-I$prefix/include/utf8cpp" \
    -DCMAKE_C_FLAGS="-I$prefix/include/minizip" -Ddraco_DIR="$deps/no-draco"
  # A static libassimp needs its own dependencies on the link line; its assimp.pc names neither.
  sed -i 's/^Libs: \(.*-lassimp[^ ]*\)$/Libs: \1 -lminizip -lz/' "$prefix/lib/pkgconfig/assimp.pc"
fi

[ $deps_only = 0 ] || exit 0
# nlohmann_json is header-only, but its package names /usr/include, whose glibc headers would
# shadow MinGW's: a copy of the headers and CMake files in the prefix points at the prefix instead.
# CLI11 (header-only, the CLI's) likewise; its host CMake package is not used (it names /usr/include).
if [ ! -f "$prefix/include/nlohmann/json.hpp" ]; then
  mkdir -p "$prefix/include" "$prefix/share/cmake"
  cp -r /usr/include/nlohmann "$prefix/include/"
  cp -r /usr/share/cmake/nlohmann_json "$prefix/share/cmake/"
fi
if [ $library_only = 0 ] && [ ! -f "$prefix/include/CLI/CLI.hpp" ]; then
  cp -r /usr/include/CLI "$prefix/include/"
fi

export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$PWD/..} CCACHE_DIR=${CCACHE_DIR:-$PWD/../.ccache}
launcher=(); command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
werror=(); [ "${AHD_WERROR:-OFF}" = ON ] && werror=(-DAHD_WARNINGS_AS_ERRORS=ON)
jobs=${AHD_JOBS:-2}  # the project's builds' parallelism (the dependencies' keep -j2)
start=$(date +%s)
cmake -S . -B $build -G Ninja -DCMAKE_BUILD_TYPE=Release -DAHD_UNITY_BUILD=OFF -DAHD_LIBRARY_ONLY=ON \
  -DCMAKE_TOOLCHAIN_FILE="$toolchain" -DAHD_WIN_DEPS_PREFIX="$prefix" "${launcher[@]}" "${werror[@]}" >/dev/null
nice -n 19 cmake --build $build -j"$jobs" --target ahd_platform_tests ahd_platform_bytes
echo "cross-windows: library build $(( $(date +%s) - start )) s"
# The whole program (the file edge and the CLI) without OpenImageIO and OpenColorIO, which have no
# MinGW build here (EXR inputs are read through OpenEXR; docs/platforms.md "Windows"). The static
# Assimp is linked into ahdpack.exe (AHD_ASSIMP_MODULE=OFF) rather than built as a DLL module.
if [ $library_only = 0 ]; then
  start=$(date +%s)
  cmake -S . -B $build-cli -G Ninja -DCMAKE_BUILD_TYPE=Release -DAHD_UNITY_BUILD=ON -DAHD_BUILD_TESTS=OFF \
    -DAHD_BUILD_BENCH=OFF -DAHD_OIIO_MODULE=OFF -DAHD_OCIO=OFF -DAHD_ASSIMP_MODULE=OFF \
    -DCMAKE_TOOLCHAIN_FILE="$toolchain" \
    -DAHD_WIN_DEPS_PREFIX="$prefix" -DZLIB_LIBRARY=/usr/x86_64-w64-mingw32/lib/libz.a "${launcher[@]}" \
    -DCMAKE_DISABLE_FIND_PACKAGE_CLI11=ON \
    "${werror[@]}" >/dev/null
  nice -n 19 cmake --build $build-cli -j"$jobs" --target ahdpack
  echo "cross-windows: ahdpack.exe build $(( $(date +%s) - start )) s"
fi

# A fresh Wine prefix per run: nothing of an earlier run (or of the user's ~/.wine) is reused.
WINEPREFIX=$(mktemp -d "${TMPDIR:-/tmp}/ahd-wine.XXXXXX")
export WINEPREFIX WINEDEBUG=-all WINEDLLOVERRIDES="mscoree,mshtml="
trap 'wineserver -k >/dev/null 2>&1 || true; rm -rf "$WINEPREFIX"' EXIT
run=(nice -n 19 wine)
if [ $tests = 1 ]; then
  start=$(date +%s)
  "${run[@]}" $build/tests/platforms/ahd_platform_tests.exe --gtest_brief=1
  echo "windows unit tests under wine: $(( $(date +%s) - start )) s"
fi
if [ $bytes = 1 ]; then
  bash scripts/compare-platform-bytes.sh reference build-x86
  rm -rf $build/platform-bytes
  start=$(date +%s)
  "${run[@]}" $build/tests/platforms/ahd_platform_bytes.exe $build/platform-bytes/windows >/dev/null
  echo "windows conversions under wine: $(( $(date +%s) - start )) s"
  bash scripts/compare-platform-bytes.sh compare build-x86/platform-bytes/x86-64-all $build/platform-bytes/windows
fi
# The CLI under Wine: the six conversions of scripts/platform-cli-bytes.sh against the x86-64 Linux
# CLI (build/ahdpack, built here when missing), then a drive-letter path with backslashes.
if [ $library_only = 0 ] && [ $bytes = 1 ]; then
  if [ ! -x build/ahdpack ]; then
    cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" >/dev/null
    nice -n 19 cmake --build build -j"$jobs" --target ahdpack
  fi
  rm -rf $build/cli-bytes
  bash scripts/platform-cli-bytes.sh run $build/cli-bytes/x86-64 build/ahdpack
  start=$(date +%s)
  bash scripts/platform-cli-bytes.sh run $build/cli-bytes/windows "${run[@]}" $build-cli/ahdpack.exe
  echo "windows CLI conversions under wine: $(( $(date +%s) - start )) s"
  bash scripts/platform-cli-bytes.sh compare $build/cli-bytes/x86-64 $build/cli-bytes/windows
  # Z: is Wine's drive for /: the plain map through an absolute drive-letter path with backslashes.
  for os in x86-64 windows; do
    mkdir -p "$build/cli-bytes/drive-$os/plain"
    cp tests/data/bakes/godot-ragdoll-plain/ragdoll_physics.exr "$build/cli-bytes/drive-$os/plain/map.exr"
  done
  build/ahdpack convert "$build/cli-bytes/drive-x86-64/plain/map.exr" -o "$build/cli-bytes/drive-x86-64/plain/map.ktx2" \
    --profile pc-bc >/dev/null
  winpath="Z:$(cd "$build/cli-bytes/drive-windows/plain" && pwd | tr / '\\')"
  "${run[@]}" $build-cli/ahdpack.exe convert "$winpath\\map.exr" -o "$winpath\\map.ktx2" --profile pc-bc >/dev/null
  rm -f "$build"/cli-bytes/drive-*/*/*.report.json
  bash scripts/compare-platform-bytes.sh compare $build/cli-bytes/drive-x86-64 $build/cli-bytes/drive-windows
  echo "windows CLI: a drive-letter path with backslashes converts to the same bytes"
  # A non-ASCII folder and file name (argv arrives as UTF-8: src/cli/win32/ahdpack.manifest; paths
  # go through files/utf8_path.h): the plain map as "plain é 光/map é.exr", the same bytes as the
  # Linux CLI's under the same name; then a missing non-ASCII file's error line names it as given.
  u8dir="plain é 光"
  for os in x86-64 windows; do
    mkdir -p "$build/cli-bytes/utf8-$os/$u8dir"
    cp tests/data/bakes/godot-ragdoll-plain/ragdoll_physics.exr "$build/cli-bytes/utf8-$os/$u8dir/map é.exr"
  done
  build/ahdpack convert "$build/cli-bytes/utf8-x86-64/$u8dir/map é.exr" -o "$build/cli-bytes/utf8-x86-64/$u8dir/map é.ktx2" \
    --profile pc-bc >/dev/null
  "${run[@]}" $build-cli/ahdpack.exe convert "$build/cli-bytes/utf8-windows/$u8dir/map é.exr" \
    -o "$build/cli-bytes/utf8-windows/$u8dir/map é.ktx2" --profile pc-bc >/dev/null
  rm -f "$build"/cli-bytes/utf8-*/*/*.report.json
  bash scripts/compare-platform-bytes.sh compare $build/cli-bytes/utf8-x86-64 $build/cli-bytes/utf8-windows
  missing="$build/cli-bytes/utf8-windows/$u8dir/absent 光.exr"
  if "${run[@]}" $build-cli/ahdpack.exe convert "$missing" -o "$build/cli-bytes/utf8-windows/absent.ktx2" \
      >/dev/null 2>"$build/cli-bytes/utf8-missing.txt"; then
    echo "cross-windows: a missing input converted" >&2; exit 1
  fi
  grep -qF "ahdpack: error: $missing: " "$build/cli-bytes/utf8-missing.txt" || {
    echo "cross-windows: the error line does not name '$missing':" >&2; cat "$build/cli-bytes/utf8-missing.txt" >&2; exit 1
  }
  echo "windows CLI: a non-ASCII name converts to the same bytes; its error line: $(head -1 "$build/cli-bytes/utf8-missing.txt")"
fi
